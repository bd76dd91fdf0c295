/* dm_render_prov.h — the provenance of a rendered picture, the same keys in dermis-render
 * and dermis-view so that two pictures compare key by key: source, scene, effects, view,
 * size, irradiance size, taps, profile, mix, exposure, light azimuth, light count, camera,
 * frames, GL renderer. Tools add their own keys after these. */
#ifndef DM_RENDER_PROV_H
#define DM_RENDER_PROV_H

#include "core/dm_prov.h"
#include "core/dm_scene.h"
#include "render/dm_render.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Initialises p for `tool` and adds the shared keys. r may be NULL (no renderer yet:
 * sizes then come from the scene). input_hash and view may be "" but not NULL. */
void dm_render_provenance(dm_provenance *p, const char *tool, const char *source, const char *input_hash,
                          const dm_scene *s, const dm_renderer *r, const char *view, double light_azimuth_deg,
                          int frames);

/* Adds every speed/accuracy setting of d (defaults resolved), the blur levels' sizes as
 * rendered, and the view's colour scale or gain (r may be NULL): a picture says which path
 * made it. */
void dm_render_settings_provenance(dm_provenance *p, const dm_render_desc *d, const dm_renderer *r);

#ifdef __cplusplus
}
#endif
#endif
