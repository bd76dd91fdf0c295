/* dm_osmesa.h — a headless OpenGL context on OSMesa (Mesa's llvmpipe), for
 * dermis-render, the render tests and the bench. lib/render never creates contexts: a
 * host like this one (or the viewer's GLFW window) makes one current first.
 *
 * Core profile 3.3 or newer (OSMesa gives 4.5 core; 4.6 is refused). OSMesaMakeCurrent
 * needs a client colour buffer even when every pass renders into FBOs: a 1x1 RGBA8 one
 * is owned here. llvmpipe's thread count comes from LP_NUM_THREADS (default: all cores).
 */
#ifndef DM_OSMESA_H
#define DM_OSMESA_H

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_osmesa dm_osmesa;

/* Creates a core-profile context and makes it current on this thread. Fails with
 * DM_ERR_GL naming what OSMesa refused. Free with dm_osmesa_destroy. */
dm_result dm_osmesa_create(dm_osmesa **out, dm_error *err);
void dm_osmesa_destroy(dm_osmesa *ctx);

#ifdef __cplusplus
}
#endif
#endif
