/* dm_viewer_session.c — dermis-view's session (dm_viewer_session.h): the status line and
 * the renderer for the edited scene, made, remade and restored when refused. */
#include "dm_viewer_session.h"

#include <stdarg.h>
#include <stdio.h>

void dm_viewer_set_status(dm_viewer *v, bool error, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(v->status, sizeof v->status, fmt, ap);
    va_end(ap);
    if (error) {
        v->failures++;
        fprintf(stderr, "error: %s\n", v->status);
    } else if (v->opt.verbose) {
        fprintf(stderr, "%s\n", v->status);
    }
}

static void list_views(dm_viewer *v)
{
    static const char *const names[] = {"final",    "specular", "diffuse",  "irradiance", "blur1",   "blur2",
                                        "blur3",    "blur4",    "blur5",    "blur6",      "blur7",   "stretch0",
                                        "stretch1", "stretch2", "stretch3", "stretch4",   "stretch5", "stretch6",
                                        "stretch7", "shadow0",  "shadow1",  "shadow2",    "shadow3", "uv",
                                        "wireframe", "curvature", "seam",   "thin"};
    v->view_count = 0;
    for (size_t i = 0; i < sizeof names / sizeof names[0] && v->view_count < DM_VIEWER_MAX_VIEWS; ++i) {
        dm_view view;
        int k;
        dm_render_plan plan;
        dm_error e = {0};
        if (!dm_view_parse(names[i], &view, &k) || dm_render_plan_build(&v->scene, view, k, &plan, &e) != DM_OK)
            continue;
        if (view == DM_VIEW_STRETCH && k >= v->assets.stretch_level_count) continue;
        if ((view == DM_VIEW_SEAM && !v->assets.seam.texels) ||
            (view == DM_VIEW_THIN && !v->assets.thin.texels && !v->assets.thin_half.texels)) continue;
        snprintf(v->view_names[v->view_count++], sizeof v->view_names[0], "%s", names[i]);
    }
}

dm_result dm_viewer_create_renderer(dm_viewer *v, dm_error *err)
{
    dm_renderer_destroy(v->r);
    v->r = NULL;
    /* Texture space is reused while the lights, scene and scales stay put (exact, tested in
     * test_render): orbiting and zooming then cost only the screen passes. */
    dm_render_desc d = {.shader_dir = v->opt.shader_dir, .width = v->opt.width, .height = v->opt.height,
                        .irradiance_size = v->irradiance_size, .timings = true, .reuse_texture_space = true};
    v->assets.scene = &v->scene;
    dm_result rc = dm_renderer_create(&v->assets, &d, &v->r, err);
    /* the live skin's weights are in v->profile already; its colour scale is not a create
     * input (refused, and left at 1, by the techniques that cannot take it) */
    if (rc == DM_OK && v->skin.changed) dm_renderer_set_profile_weights(v->r, &v->profile, v->skin.scale_rgb, NULL);
    if (rc == DM_OK) list_views(v);
    v->dirty = true;
    return rc;
}

/* On failure says why (e.g. the pack holds no data for an effect its scene had off). */
bool dm_viewer_rebuild(dm_viewer *v, const dm_scene *previous, int previous_irr, const char *what)
{
    dm_error err = {0};
    if (dm_viewer_create_renderer(v, &err) == DM_OK) {
        dm_viewer_set_status(v, false, "%s", what);
        return true;
    }
    char why[sizeof err.detail];
    snprintf(why, sizeof why, "%s", err.detail);
    v->scene = *previous;
    v->irradiance_size = previous_irr;
    dm_error err2 = {0};
    if (dm_viewer_create_renderer(v, &err2) != DM_OK) fprintf(stderr, "error: cannot restore the renderer: %s\n", err2.detail);
    dm_viewer_set_status(v, true, "%s refused: %s", what, why);
    return false;
}
