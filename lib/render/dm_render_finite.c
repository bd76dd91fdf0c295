/* dm_render_finite.c — the last line of defence before a picture is written: a view holding
 * NaN or infinite values is refused, with the targets where they arose. */
#include <stdio.h>
#include <stdlib.h>

#include "core/dm_math.h"
#include "render/dm_render.h"

/* "irradiance (4096), screen (17)": the targets holding NaN or infinite values. */
static void targets_with_nonfinite(dm_renderer *r, char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (int i = 0; i < dm_renderer_target_count(r); ++i) {
        dm_target_info t;
        dm_renderer_target_info(r, i, &t);
        size_t n = (size_t)t.width * (size_t)t.height * (size_t)t.channels;
        float *v = malloc(n * sizeof *v);
        dm_error ignored = {0};
        size_t bad = v && dm_renderer_read_target(r, i, v, &ignored) == DM_OK ? dm_count_nonfinite(v, n, NULL) : 0;
        free(v);
        if (bad && used < size)
            used += (size_t)snprintf(out + used, size - used, "%s%s (%zu)", used ? ", " : "", t.name, bad);
    }
}

dm_result dm_renderer_check_finite(dm_renderer *r, dm_error *err)
{
    int w, h;
    dm_renderer_view_size(r, &w, &h);
    size_t n = (size_t)w * (size_t)h * 4, first;
    float *px = malloc(n * sizeof *px);
    if (!px) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "the finiteness check: cannot allocate %zu floats", n);
    dm_result rc = dm_renderer_read_view(r, px, err);
    size_t bad = rc == DM_OK ? dm_count_nonfinite(px, n, &first) : 0;
    if (bad) {
        float value = px[first];
        char where[1024];
        targets_with_nonfinite(r, where, sizeof where);
        const dm_render_plan *plan = dm_renderer_plan(r);
        rc = dm_fail(err, DM_ERR_NON_FINITE,
                     "view %s: %zu of %zu values are NaN or infinite (the first at pixel (%zu, %zu) from the "
                     "top left, channel %zu: %g); targets holding such values: %s; no picture written",
                     dm_view_name(plan->view), bad, n, first / 4 % (size_t)w, (size_t)h - 1 - first / 4 / (size_t)w,
                     first % 4, (double)value, where[0] ? where : "none besides the view");
    }
    free(px);
    return rc;
}
