#include "host/dm_osmesa.h"

#include <stdint.h>
#include <stdlib.h>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>

/* Sanitizer builds (make config=sanitize): libOSMesa keeps a few allocations until exit
 * (16 + 304 bytes from its own code, and the records OSMesaMakeCurrent makes), which
 * LeakSanitizer reports and which turn a tool's exit code into 23. Suppressed here, built
 * into every binary that makes an OSMesa context, for allocations whose stack passes
 * through libOSMesa.so only: a leak of dermis's own is still reported. */
#if defined(__SANITIZE_ADDRESS__)
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) { return "leak:libOSMesa.so\n"; }
const char *__lsan_default_options(void);
const char *__lsan_default_options(void) { return "print_suppressions=0"; }
#endif

struct dm_osmesa {
    OSMesaContext ctx;
    uint32_t pixel; /* the 1x1 client buffer OSMesaMakeCurrent insists on */
};

dm_result dm_osmesa_create(dm_osmesa **out, dm_error *err)
{
    *out = NULL;
    dm_osmesa *o = calloc(1, sizeof *o);
    if (!o) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "osmesa: cannot allocate the context record");
    const int attribs[] = {OSMESA_FORMAT,        OSMESA_RGBA, OSMESA_DEPTH_BITS, 0, OSMESA_STENCIL_BITS, 0,
                           OSMESA_ACCUM_BITS,    0,           OSMESA_PROFILE,    OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
    o->ctx = OSMesaCreateContextAttribs(attribs, NULL);
    if (!o->ctx) {
        free(o);
        return dm_fail(err, DM_ERR_GL, "osmesa: OSMesaCreateContextAttribs refused a 3.3 core profile context");
    }
    if (!OSMesaMakeCurrent(o->ctx, &o->pixel, GL_UNSIGNED_BYTE, 1, 1)) {
        OSMesaDestroyContext(o->ctx);
        free(o);
        return dm_fail(err, DM_ERR_GL, "osmesa: OSMesaMakeCurrent failed on a 1x1 RGBA8 buffer");
    }
    *out = o;
    return DM_OK;
}

void dm_osmesa_destroy(dm_osmesa *o)
{
    if (!o) return;
    OSMesaMakeCurrent(NULL, NULL, 0, 0, 0);
    OSMesaDestroyContext(o->ctx);
    free(o);
}
