/* dermis-view --reference: the comparison with a ground truth through the shared
 * render/dm_render_refcmp.h, so the viewer shows the numbers dermis-render prints. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dm_viewer_compare.h"

dm_result dm_viewer_compare_load(dm_viewer *v, const char *path, dm_error *err)
{
    dm_viewer_compare *c = &v->cmp;
    dm_result rc = dm_refcmp_load(path, &c->ref, err);
    if (rc != DM_OK) return rc;
    snprintf(c->path, sizeof c->path, "%s", path);
    c->loaded = c->on = true;
    c->layout = DM_REFCMP_SIDE_BY_SIDE;
    c->split = 0.5f;
    c->error_scale = (float)DM_REFCMP_DEFAULT_ERROR_SCALE;
    if (c->ref.mode == DM_REFCMP_TEXTURE_SPACE) {
        v->irradiance_size = c->ref.width;
    } else {
        v->opt.width = c->ref.width;
        v->opt.height = c->ref.height;
    }
    return DM_OK;
}

void dm_viewer_compare_free(dm_viewer *v)
{
    dm_refcmp_ref_free(&v->cmp.ref);
    memset(&v->cmp, 0, sizeof v->cmp);
}

bool dm_viewer_set_compare(dm_viewer *v, const char *mode)
{
    dm_viewer_compare *c = &v->cmp;
    if (!c->loaded) {
        dm_viewer_set_status(v, true, "compare %s: no reference (start with --reference REF.exr)", mode);
        return false;
    }
    dm_refcmp_layout l;
    if (!strcmp(mode, "off")) {
        c->on = false;
    } else if (dm_refcmp_layout_parse(mode, &l)) {
        c->on = true;
        c->layout = l;
    } else {
        dm_viewer_set_status(v, true, "compare '%s': expected off, side, split or error", mode);
        return false;
    }
    v->dirty = true;
    return true;
}

void dm_viewer_cycle_compare(dm_viewer *v)
{
    dm_viewer_compare *c = &v->cmp;
    if (!c->loaded && v->tsplit) { /* the technique split uses the same layouts */
        c->layout = (dm_refcmp_layout)((c->layout + 1) % DM_REFCMP_LAYOUT_COUNT);
        v->dirty = true;
        return;
    }
    if (!c->loaded) {
        dm_viewer_set_status(v, false, "no reference to compare with (--reference REF.exr)");
        return;
    }
    if (!c->on) dm_viewer_set_compare(v, "side");
    else if (c->layout + 1 < DM_REFCMP_LAYOUT_COUNT)
        dm_viewer_set_compare(v, dm_refcmp_layout_name((dm_refcmp_layout)(c->layout + 1)));
    else dm_viewer_set_compare(v, "off");
}

bool dm_viewer_compare_frame(dm_viewer *v)
{
    dm_viewer_compare *c = &v->cmp;
    dm_error err = {0};
    int w, h;
    dm_renderer_view_size(v->r, &w, &h);
    if (w != c->ref.width || h != c->ref.height) {
        dm_viewer_set_status(v, true, "compare: the render is %dx%d, the reference %s %dx%d (irradiance size or "
                             "picture size changed)", w, h, c->path, c->ref.width, c->ref.height);
        c->on = false;
        v->dirty = true;
        return false;
    }
    size_t n = (size_t)w * h;
    float *px = malloc(n * 4 * sizeof *px), *rel = malloc(n * sizeof *rel);
    bool ok = px && rel;
    if (!ok) dm_viewer_set_status(v, true, "compare: cannot allocate %dx%d", w, h);
    if (ok && (dm_renderer_read_view(v->r, px, &err) != DM_OK ||
               dm_refcmp_stats_compute(c->ref.rgba, px, w, h, &c->stats, rel, &err) != DM_OK)) {
        dm_viewer_set_status(v, true, "compare: %s", err.detail);
        ok = false;
    }
    if (ok) {
        c->has_stats = true;
        dm_refcmp_stats_text(&c->stats, c->ref.mode, c->text, sizeof c->text);
        /* the legend stays clear of the panel (when shown) and of the attribution line */
        dm_refcmp_view view = {.layout = c->layout, .split = c->split, .error_scale = c->error_scale,
                               .margin_right_px = v->show_panel ? 346 : 0, .margin_bottom_px = 24};
        dm_refcmp_compose(c->ref.rgba, px, rel, w, h, &c->stats, &view, v->rgba, v->opt.width, v->opt.height);
    }
    free(px);
    free(rel);
    return ok;
}
