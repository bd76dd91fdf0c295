/* dm_render_synth.h — a synthetic scene and its GPU-ready assets, built in memory from
 * lib/core alone (no pack, no bake library): a UV sphere or a flat quad, their exact
 * stretch maps, the Beckmann and directional LUTs evaluated with core/dm_brdf.h, a
 * smooth sky as environment. For tests, the bench and dermis-render --synthetic until
 * packs exist.
 *
 * The scene is filled field by field here (dm_scene_defaults arrives with the scene
 * parser): all effects on, one directional light casting a shadow, gems3-skin, 7 taps.
 * Sizes: the sphere has radius 1 mesh unit (mm_per_unit 50: 50 mm); the quad has side
 * quad_side_mm, lies in z = 0 facing +z and maps to UV [0, 1]².
 */
#ifndef DM_RENDER_SYNTH_H
#define DM_RENDER_SYNTH_H

#include <stdint.h>

#include "core/dm_result.h"
#include "core/dm_scene.h"
#include "render/dm_render.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum dm_synth_shape { DM_SYNTH_SPHERE = 0, DM_SYNTH_QUAD } dm_synth_shape;

/* Zero means default. */
typedef struct dm_synth_options {
    dm_synth_shape shape;
    int sphere_segments, sphere_rings; /* 96 x 96: 18,240 triangles */
    int quad_cells;                    /* cells per side, 16 */
    float quad_side_mm;                /* 64 */
    float quad_uv_inset;               /* the quad's UVs span [inset, 1 − inset]², leaving a
                                        * gutter around one chart; 0, in [0, 0.45] */
    int stretch_size;                  /* stretch map texels per side, 256 */
    int beckmann_size;                 /* 256 */
    int directional_size;              /* 32 (rho_dt, env-BRDF scale and bias) */
} dm_synth_options;

typedef struct dm_synth {
    dm_scene scene;          /* edit freely before dm_renderer_create */
    dm_render_assets assets; /* assets.scene points at scene: do not copy the struct */
    int triangle_count;
    /* owned arrays, freed by dm_synth_free */
    float *vertices;
    uint32_t *indices;
    uint8_t *beckmann, *mask, albedo[4];
    float *rho_dt, *env_brdf, *stretch, *env, *background;
} dm_synth;

/* Builds the scene and its assets; free with dm_synth_free. */
dm_result dm_synth_create(const dm_synth_options *opt, dm_synth **out, dm_error *err);
void dm_synth_free(dm_synth *s);

/* Sets every field of s: the synthetic scene described above (camera on +z looking at
 * the origin from `distance` mesh units). */
void dm_synth_scene(dm_scene *s, float distance);

#ifdef __cplusplus
}
#endif
#endif
