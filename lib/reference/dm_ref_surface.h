/* dm_ref_surface.h — the skin surface as the ground truth sees it: the pack's mesh, maps,
 * lights and environment, ready for CPU shading (dm_ref_shade.h) and ray casting.
 *
 * What comes in is what the renderer uploads (dm_render_assets in lib/render, which the
 * offline side does not link): the dermis vertex layout (DM_PACK_VERTEX_*), the maps, the
 * environment's SH, prefiltered levels and background. Absent maps mean what they mean to
 * the renderer: albedo white, no normal map (the interpolated normal), specular map 1,
 * roughness the scene's constant.
 *
 * Units: the mesh stays in mesh units (mesh, for dm_uv_raster and dm_reference, with
 * scene.mm_per_unit); every position the shading sees is in mm (× mm_per_unit), and the
 * ray caster works in mm. Point lights are placed at position × mm_per_unit. The renderer's
 * lights have no distance falloff: neither do these.
 *
 * Exact where the renderer tabulates: ρdt(c, m) — the energy term (1 − ρs·ρdt) on light in
 * and out, and the split-sum environment factor F0·scale + bias, which is the same
 * integral — comes from dm_ks_directional (lib/core/dm_brdf.h, 48 Gauss–Legendre nodes,
 * < 1e-6) tabulated at creation on a grid uniform in √c (1024 intervals, so the steep
 * grazing end is resolved) and, with a roughness map, in m (64 intervals); linear between.
 * Measured against direct evaluation (tests/unit/test_ref_shade.c): ≤ 1.3e-5 at m = 0.3;
 * at m = 0.01, 3.1e-4 in the first, most grazing interval (c < 1e-6) and 2.7e-5 from
 * c = 1e-3; with a roughness map (linear in m too) 1.9e-4. Without a roughness map the
 * table is one column at the scene's m. Specular D is dm_beckmann in double.
 *
 * Ownership: a surface borrows desc's arrays and textures (the pack's mapping) for its
 * whole life; it owns its mesh copy, tables and ray caster. Read-only after creation:
 * any number of threads may shade with it at once.
 */
#ifndef DM_REF_SURFACE_H
#define DM_REF_SURFACE_H

#include <stdbool.h>
#include <stdint.h>

#include "mesh/dm_mesh.h"
#include "mesh/dm_raycast.h"
#include "reference/dm_ref_texture.h"
#include "pack/dm_pack.h"
#include "core/dm_profile.h"
#include "core/dm_result.h"
#include "core/dm_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_REF_ENV_LEVELS_MAX = 6, DM_REF_VERTEX_FLOATS = DM_PACK_VERTEX_STRIDE / 4 };

typedef struct dm_ref_surface_desc {
    const dm_scene *scene;     /* never NULL: material, lights, effects, environment, mix */
    const dm_profile *profile; /* NULL: scene->profile */
    const float *vertices;     /* vertex_count × DM_REF_VERTEX_FLOATS, the dermis layout */
    int32_t vertex_count;
    const uint32_t *indices;   /* index_count (multiple of 3), counter-clockwise = front */
    int32_t index_count;
    dm_ref_texture albedo;        /* RGBA8_SRGB (texels NULL: white) */
    dm_ref_texture normal_map;    /* RGBA8 tangent space, green up (NULL: none) */
    dm_ref_texture specular_map;  /* R8 or RGBA8, red scales rho_s (NULL: 1) */
    dm_ref_texture roughness_map; /* R8, m (NULL: scene->roughness) */
    bool has_env_sh;
    float env_sh[9][3];           /* radiance SH (dm_sh.h order), RGB */
    int env_level_count;          /* 0..DM_REF_ENV_LEVELS_MAX */
    float env_level_m[DM_REF_ENV_LEVELS_MAX];
    dm_ref_texture env_levels[DM_REF_ENV_LEVELS_MAX]; /* equirect, float (repeat_u set) */
    dm_ref_texture env_background;                    /* equirect, float (NULL: none) */
} dm_ref_surface_desc;

/* Fills desc from an open pack, as lib/render/input/dm_render_pack.c reads it: mesh.vertices
 * (the dermis layout is checked), mesh.indices, albedo, normal, specular, roughness,
 * env.sh (order 2), env.specular (its layers' m from the entry's provenance m0..m5),
 * env.background. The profile is the pack's "profile" entry when there is one, else
 * scene->profile, written to *profile (which desc->profile then points to). scene is
 * the caller's (usually dm_pack_scene of the same pack, maybe with a changed size). */
dm_result dm_ref_surface_desc_from_pack(const dm_pack *pack, const dm_scene *scene, dm_profile *profile,
                                        dm_ref_surface_desc *desc, dm_error *err);

/* Which terms are on: the renderer's plan for these effects (lib/render/input/dm_render_plan.c). */
typedef struct dm_ref_terms {
    bool subsurface;   /* diffuse from the convolution of the irradiance atlas */
    bool specular;     /* KS specular per light */
    bool energy;       /* 1 − ρs·ρdt in and out (energy_conservation with specular) */
    bool env_diffuse;  /* SH irradiance (environment_lighting with an env.sh) */
    bool env_specular; /* split-sum environment specular (environment_lighting with specular) */
    bool background;   /* environment behind the head (environment_lighting, env_background) */
    bool shadows;      /* shadow rays for the lights that cast */
} dm_ref_terms;

typedef struct dm_ref_surface {
    dm_scene scene;
    dm_profile profile;
    dm_ref_terms terms;
    dm_ref_surface_desc desc; /* borrowed arrays and textures; scene/profile point here */
    dm_mesh mesh;             /* mesh units: one position per vertex, per-corner uv and normal */
    dm_raycast *rays;         /* in mm */
    double eps_mm;            /* secondary-ray offset (dm_raycast_epsilon_mm) */
    double mm_per_unit;
    /* lights, resolved like the renderer's frame_lights (no rotation): directional
     * (w = 0: unit direction towards the light) or point (w = 1: position in mm) */
    int light_count;
    double light_pos[DM_SCENE_MAX_LIGHTS][4];
    double light_color[DM_SCENE_MAX_LIGHTS][3]; /* colour × intensity */
    bool light_shadow[DM_SCENE_MAX_LIGHTS];     /* a shadow ray is cast for this light */
    double env_rotation_rad;
    /* ρdt table: rho_m_count columns of rho_c_count values */
    int rho_c_count, rho_m_count;
    double *rho;
} dm_ref_surface;

/* Builds the surface: validates desc (sizes, indices in range, finite values), copies the
 * mesh, builds the ray caster, resolves the lights and the terms, tabulates ρdt on
 * thread_count threads (0 = all cores). Free with dm_ref_surface_destroy. */
dm_result dm_ref_surface_create(const dm_ref_surface_desc *desc, int thread_count, dm_ref_surface **out,
                                dm_error *err);
void dm_ref_surface_destroy(dm_ref_surface *s);

/* ρdt(c, m) = F0·scale + bias (F0 = DM_SKIN_F0) from the table; c clamped to [0, 1], m to
 * [0, 1]. With no roughness map, m is the table's one column whatever is asked. */
double dm_ref_surface_rho_dt(const dm_ref_surface *s, double c, double m);

/* Everything the shading needs at one point of the surface. */
typedef struct dm_ref_point {
    int32_t triangle;
    double b1, b2;
    double p_mm[3];   /* position */
    double ng[3];     /* unit front normal of the triangle (geometric) */
    double n[3];      /* interpolated vertex normal, normalised (ng where it vanishes) */
    double N[3];      /* shading normal: n perturbed by the normal map (dm_shading_normal) */
    double uv[2];
    double m;         /* min(roughness, 1) */
    double rho_s;     /* scene rho_s × specular map */
    double albedo[3]; /* linear, ≥ 0 */
} dm_ref_point;

/* The point at barycentrics (b1, b2) of triangle tri (attributes interpolated linearly, as
 * the renderer's rasterizer does in either pass). */
void dm_ref_surface_point(const dm_ref_surface *s, int32_t tri, double b1, double b2, dm_ref_point *p);

/* Where p lies on the smooth surface its interpolated normals describe, in mm: the point
 * shadow rays start from. After Hanika, "Hacking the shadow terminator" (Ray Tracing Gems
 * II, 2021): P = p->p_mm is projected onto the tangent plane of each corner i (position
 * v_i, unit vertex normal n_i), keeping only lifts (h_i = dot(P − v_i, n_i) < 0), and
 *   out = P − ½ Σ w_i min(h_i, 0) n_i      (w the barycentrics of p).
 * The ½ is ours: on a quadric patch the facet lies below the surface by ½ Σ w_i (P − v_i)ᵀ
 * H (P − v_i) and Hanika's blend of the projections (without the ½) lies above it by
 * exactly as much, so their midpoint is the surface to second order (measured on a 24 × 12
 * sphere: facets up to 1.7 % of R inside, this point 0.04 % of R). Hanika's full lift
 * would start rays above the mesh where the surface turns from the light, so they pass
 * over the facets beside it. A concave or flat corner leaves P where it is; a corner whose
 * normal is zero lifts nothing: out is finite for finite vertices, zero-area triangles
 * included. */
void dm_ref_surface_smooth_point(const dm_ref_surface *s, const dm_ref_point *p, double out_mm[3]);

#ifdef __cplusplus
}
#endif
#endif
