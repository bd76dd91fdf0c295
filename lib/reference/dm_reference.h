/* dm_reference.h — the ground truth of subsurface diffusion: the exact surface convolution
 *
 *   S_k(x) = ∫_surface I(x′) G(v_k, ‖P(x) − P(x′)‖) dA(x′),   D(x) = Σ_k w_k S_k(x)
 *
 * over the whole mesh with 3-D Euclidean distances in mm (light crosses UV seams and
 * reaches the other side of ears, lips and eyelids), exact triangle areas, and G the
 * unit-integral radial Gaussian of dm_profile.h. Nothing here is shared with the
 * texture-space renderer but the irradiance it is given.
 *
 * THE IRRADIANCE I. An atlas (rows bottom-up, RGBA, alpha = coverage in [0, 1]) read at a
 * surface point through the UV of that point: bilinear over the 2×2 texels around it,
 * weighted by coverage and renormalised (Σ w α I / Σ w α; gutters drop out, as they do in
 * the renderer's blurs). Where no texel of the 2×2 is covered (slivers, zero-UV-area
 * triangles such as the head's eyes) the nearest covered texel within 2 texels is used;
 * beyond that I = 0 (such area is counted in dm_reference_stats.unlit_area_mm2).
 *
 * THE QUADRATURE (each bound is tested in tests/unit/test_reference.c).
 * - Cut: each Gaussian is integrated out to cut_sigma·σ (default 4). The mass beyond,
 *   exp(−cut²/2) (3.4e-4 at 4σ, exact on a plane), is added as that fraction of I(x), the
 *   value at the target point itself.
 * - Wide Gaussians (σ ≥ wide_texels · the atlas texel's size in mm, 95th percentile over
 *   the triangles; default 4): the surface is cut into "texel elements", each triangle
 *   clipped against the cells between texel centres in UV (exact areas, mapped to mm by
 *   the triangle's Jacobian; I is bilinear inside each), each element a point at its
 *   centroid with I there. Composite centroid rule: its O(h²) term integrates ∇²(I·G),
 *   which vanishes over the plane for smooth I.
 * - Narrow Gaussians (the rest): around each target the triangles within the cut are
 *   subdivided on the fly into n² congruent sub-triangles of edge ≤ spacing_sigma·σ
 *   (default 0.3), only those whose centroid lies within the cut, I read at each centroid.
 *   Gaussians of close widths (σ ratio < 1.5) share one point set.
 * - Triangles of zero 3-D area carry no mass; zero-UV-area triangles carry their 3-D area
 *   with I read at their (degenerate) UV.
 *
 * Units: positions in mesh units × mm_per_unit; variances in mm²; S_k and D in the units
 * of I (G integrates to 1).
 *
 * Determinism: every target is computed independently in a fixed order; results are
 * byte-identical for any thread count and any split of the targets (tiles).
 */
#ifndef DM_REFERENCE_H
#define DM_REFERENCE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "mesh/dm_mesh.h"
#include "pack/dm_pack.h"
#include "core/dm_profile.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    /* Gaussians one reference evaluates: a profile's (≤ DM_PROFILE_MAX_GAUSSIANS), or more
     * for the dense representation of a radial profile (dm_reference_kernel_from_source). */
    DM_REFERENCE_GAUSSIANS_MAX = 32
};

/* What is convolved: Gaussians of variance variance_mm2[k] (ascending, > 0) with per-channel
 * weights (D = Σ_k weight[k] · S_k). For a profile: the renderer's weights, each channel
 * divided by its sum (dm_reference_kernel_from_profile). */
typedef struct dm_reference_kernel {
    int count; /* 1..DM_REFERENCE_GAUSSIANS_MAX */
    double variance_mm2[DM_REFERENCE_GAUSSIANS_MAX];
    double weight[DM_REFERENCE_GAUSSIANS_MAX][3];
} dm_reference_kernel;

/* The profile's Gaussians with each channel's weights normalised to sum 1, as the renderer
 * does (u_level_weight). DM_ERR_RANGE when a channel sums to 0. */
dm_result dm_reference_kernel_from_profile(const dm_profile *p, dm_reference_kernel *k, dm_error *err);

/* A radial profile that is not a sum of a few Gaussians (dipole, multipole: a
 * dm_profile_source) represented by gaussian_count (2..32) Gaussians with log-spaced widths
 * and non-negative weights (dm_profile_represent), each channel normalised to sum 1 as the
 * renderer normalises its profiles. rel_error (may be NULL) receives the representation's
 * relative L2 error per channel, sqrt(∫ r (R − ΣG)² dr / ∫ r R² dr): the tool reports it
 * beside the profile fits it is compared with. */
struct dm_profile_source;
dm_result dm_reference_kernel_from_source(const struct dm_profile_source *s, int gaussian_count,
                                          dm_reference_kernel *k, double rel_error[3], dm_error *err);

/* The irradiance atlas (borrowed; the caller keeps it alive while the reference exists). */
typedef struct dm_reference_atlas {
    int width, height;   /* texels, 1..16384 */
    const float *rgba;   /* width*height*4, rows bottom-up, alpha = coverage in [0, 1] */
} dm_reference_atlas;

typedef struct dm_reference_options {
    double cut_sigma;      /* 0 = 4; [2, 8] */
    double spacing_sigma;  /* narrow Gaussians' sub-triangle edge in σ; 0 = 0.3; [1/32, 1] */
    double wide_texels;    /* σ (in texels) from which texel elements are used; 0 = 4; ≥ 1,
                            * +inf: never (every Gaussian by subdivision) */
    int thread_count;      /* 0 = all cores */
    /* Called now and then from the calling thread with the fraction done, 0..1; may be NULL. */
    void (*progress)(void *user, double fraction);
    void *progress_user;
} dm_reference_options;

typedef struct dm_reference_stats {
    int64_t element_count;      /* texel elements built */
    int narrow_gaussians, wide_gaussians;
    double texel_mm;            /* the atlas texel's size used for the split (95th pct), mm */
    double surface_area_mm2;    /* Σ triangle areas */
    double unlit_area_mm2;      /* area where I could not be read (no covered texel near),
                                 * counted over the texel elements (0 without a wide Gaussian) */
    int64_t zero_area_triangles, zero_uv_area_triangles;
    double build_ms;
} dm_reference_stats;

typedef struct dm_reference dm_reference;

/* Builds what every evaluation reads: positions in mm, the triangle grid, texel elements.
 * mesh must be valid (dm_mesh_validate); it and the atlas are borrowed for the lifetime
 * of the reference. mm_per_unit > 0 and finite. opt may be NULL. */
dm_result dm_reference_create(const dm_mesh *mesh, double mm_per_unit, const dm_reference_atlas *atlas,
                              const dm_reference_kernel *kernel, const dm_reference_options *opt,
                              dm_reference **out, dm_error *err);
void dm_reference_destroy(dm_reference *ref);
void dm_reference_get_stats(const dm_reference *ref, dm_reference_stats *stats);

/* A point on the surface where D is wanted: triangle and barycentric coordinates
 * (b1, b2 of corners 1 and 2; corner 0 gets 1 − b1 − b2). */
typedef struct dm_reference_target {
    int32_t triangle;
    float b1, b2;
} dm_reference_target;

/* Evaluates target_count targets: rgb (target_count*3 floats) receives D; levels (may be
 * NULL) receives target_count * kernel.count * 3 floats, S_k per target (k-major within
 * a target: levels[(t * count + k) * 3 + c]). Runs on opt.thread_count threads; reports
 * progress over these targets. Always finite. */
dm_result dm_reference_eval(const dm_reference *ref, const dm_reference_target *targets, size_t target_count,
                            float *rgb, float *levels, dm_error *err);

/* ---- texture space --------------------------------------------------------------- */

/* The targets of an atlas: every texel whose coverage alpha > 0, in row-major order
 * (rows bottom-up), located on the mesh by dm_uv_raster at the atlas size (a covered
 * texel the raster leaves empty is put on the nearest covered texel's triangle, with its
 * own UV extrapolated). texel_of receives each target's texel index j*width + i.
 * *targets and *texel_of are malloc'd (free both). */
dm_result dm_reference_atlas_targets(const dm_mesh *mesh, const dm_reference_atlas *atlas, int thread_count,
                                     dm_reference_target **targets, int64_t **texel_of, size_t *count,
                                     dm_error *err);


/* ---- memory ---------------------------------------------------------------------- */

/* What a dermis-reference run will hold at its peak, from its options, before any work; the
 * tool refuses (core/dm_memory.h) what exceeds the memory available. Bytes; N the
 * texture-space size, A the frame's atlas, F = A·k its fine atlas (k the atlas samples,
 * reduced until F <= 8192), W x H the frame, K the Gaussians kept with --levels:
 *   base           DM_REFERENCE_MEMORY_BASE_SIZE (the libraries, the mesh, Embree) + the pack
 *                  (mapped and read whole when verified)
 *   texture space  the larger of: the irradiance pass, the renderer's own estimate at N
 *                  (render/dm_render_memory.h: its driver and the pack's textures included;
 *                  0 with --irradiance FILE) + the atlas N² x 16 + the pack (open beside it:
 *                  its seam and thin-part maps alone are N² x 48); and base + the convolution,
 *                  N² x (16 atlas + 16 lookup + 20 targets + 4 raster + 48 texel elements,
 *                  built then sorted + 12 results + 16 planes [+ 24 K levels])
 *   frame          base + the larger of: the CPU irradiance, A² x 16 + F² x 20 (the fine atlas
 *                  and its triangle per texel); and the convolution, A² x (16 + 16 + 48
 *                  elements); + W x H x 80 (hits, targets, results, the image, its planes, the
 *                  display) + W x H x 44 P² (P the pixel samples: each sub-pixel ray's hit,
 *                  index, target and result) [+ W x H x (12 + 44 R²) with refine R: every
 *                  pixel counted, though the head at 1280x720 refines a fraction]
 * Every texel is counted as covered (the head covers about half its atlas): the estimate is
 * high by up to a third where the convolution dominates. Measured (docs/dermis-reference.md):
 * within 0.9..1.3 of the peak RSS. */
#define DM_REFERENCE_MEMORY_BASE_SIZE ((uint64_t)64 << 20)

typedef struct dm_reference_memory_options {
    int texture_space;   /* N, or 0 for a frame */
    int level_count;     /* K Gaussians written as levels (--levels), else 0 */
    uint64_t irradiance_render_size; /* texture space: the renderer's estimate for I at N, 0 when
                                      * I comes from a file */
    int width, height;   /* frame; 0 = the scene's */
    int atlas_size;      /* frame; 0 = DM_REF_FRAME_ATLAS_DEFAULT (4096) */
    int atlas_samples;   /* frame; 0 = 4 */
    int pixel_samples;   /* frame; 0 = 3 */
    int refine_samples;  /* frame; 0 = off */
} dm_reference_memory_options;

typedef struct dm_reference_memory {
    uint64_t base_size, irradiance_size, convolution_size, pixels_size, total_size;
} dm_reference_memory;

/* The estimate for a run on `pack` (its scene gives the frame's default size). */
void dm_reference_memory_estimate(const dm_pack *pack, const dm_reference_memory_options *o,
                                  dm_reference_memory *out);
/* The estimate against the memory available: DM_ERR_OUT_OF_MEMORY with both numbers and the
 * option to lower (core/dm_memory.h) when it does not fit. */
dm_result dm_reference_memory_check(const dm_pack *pack, const dm_reference_memory_options *o, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
