/* dermis-view: the subsurface technique at runtime (key T, the panel) and two techniques
 * side by side (shift+T). The comparison reuses dm_viewer_compare's machinery
 * (render/dm_render_refcmp.h): the other technique's final linear frame stands where a
 * reference would, so the split divider, the side-by-side and error-map layouts and the
 * per-channel difference statistics are the same code as --reference. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dm_viewer_technique.h"

/* What technique t needs from the pack, NULL when the pack holds it: texture-space the stretch
 * chain, pre-integrated its table and curvature map (packed only for a scene of that
 * technique); screen-space nothing (its kernel is fitted from the profile when not packed). */
const char *dm_viewer_technique_missing(const dm_viewer *v, dm_sss_technique t)
{
    const dm_render_assets *a = &v->assets;
    if (t == DM_SSS_TEXTURE_SPACE && (a->stretch_level_count < 1 || !a->stretch[0].texels))
        return "the stretch chain (pack a texture-space scene)";
    if (t == DM_SSS_PRE_INTEGRATED && (!a->preintegrated.texels || !a->curvature.texels))
        return "the pre-integrated table and curvature map (pack a pre-integrated scene)";
    return NULL;
}

/* The next technique after t that is implemented and that the pack supports; t when none. */
static dm_sss_technique next(const dm_viewer *v, dm_sss_technique t)
{
    for (int k = 1; k < DM_SSS_TECHNIQUE_COUNT; ++k) {
        dm_sss_technique c = (dm_sss_technique)(((int)t + k) % DM_SSS_TECHNIQUE_COUNT);
        if (dm_sss_technique_available(c) && !dm_viewer_technique_missing(v, c)) return c;
    }
    return t;
}

static dm_sss_technique other(const dm_viewer *v)
{
    return next(v, v->scene.sss_technique);
}

bool dm_viewer_set_technique(dm_viewer *v, const char *name)
{
    int t = -1;
    for (int k = 0; k < DM_SSS_TECHNIQUE_COUNT; ++k)
        if (!strcmp(name, dm_sss_technique_name((dm_sss_technique)k))) t = k;
    if (t < 0 || !dm_sss_technique_available((dm_sss_technique)t)) {
        dm_viewer_set_status(v, true, "technique '%s': expected texture-space, screen-space or pre-integrated", name);
        return false;
    }
    const char *missing = dm_viewer_technique_missing(v, (dm_sss_technique)t);
    if (missing) {
        dm_viewer_set_status(v, true, "technique %s: this pack lacks %s", name, missing);
        return false;
    }
    if (v->scene.sss_technique == (dm_sss_technique)t) return true;
    dm_scene prev = v->scene;
    v->scene.sss_technique = (dm_sss_technique)t;
    char what[64];
    snprintf(what, sizeof what, "technique %s", name);
    bool ok = dm_viewer_rebuild(v, &prev, v->irradiance_size, what);
    dm_render_plan plan; /* texture views do not exist in screen space: back to the picture */
    dm_error err = {0};
    if (dm_render_plan_build(&v->scene, v->view, v->view_index, &plan, &err) != DM_OK)
        v->view = DM_VIEW_FINAL, v->view_index = 0;
    return ok;
}

void dm_viewer_cycle_technique(dm_viewer *v)
{
    dm_sss_technique t = other(v);
    if (t == v->scene.sss_technique) {
        dm_viewer_set_status(v, true, "technique: this pack supports only %s (texture-space needs the stretch chain, "
                             "pre-integrated its table and curvature map)", dm_sss_technique_name(t));
        return;
    }
    dm_viewer_set_technique(v, dm_sss_technique_name(t));
}

bool dm_viewer_set_technique_split(dm_viewer *v, bool on)
{
    if (on && v->cmp.on) {
        dm_viewer_set_status(v, true, "technique split: the --reference comparison is on (C turns it off)");
        return false;
    }
    if (!on) {
        dm_renderer_destroy(v->r_other);
        v->r_other = NULL;
    }
    if (on && !v->cmp.loaded) { /* the comparison's layout, not in use for a reference */
        v->cmp.layout = DM_REFCMP_SPLIT;
        if (!(v->cmp.split > 0)) v->cmp.split = 0.5f;
        if (!(v->cmp.error_scale > 0)) v->cmp.error_scale = (float)DM_REFCMP_DEFAULT_ERROR_SCALE;
    }
    v->tsplit = on;
    v->dirty = true;
    if (on)
        dm_viewer_set_status(v, false, "left: %s, right: %s", dm_sss_technique_name(other(v)),
                             dm_sss_technique_name(v->scene.sss_technique));
    return true;
}

/* The second renderer follows the scene; recreated when set_scene says the passes differ. */
static bool render_other(dm_viewer *v, const dm_frame_options *fo, dm_error *err)
{
    v->scene_other = v->scene;
    v->scene_other.sss_technique = other(v);
    if (v->r_other && dm_renderer_set_scene(v->r_other, &v->scene_other, err) != DM_OK) {
        dm_renderer_destroy(v->r_other);
        v->r_other = NULL;
    }
    if (!v->r_other) {
        dm_render_assets a = v->assets;
        a.scene = &v->scene_other;
        dm_render_desc d = {.shader_dir = v->opt.shader_dir, .width = v->opt.width, .height = v->opt.height,
                            .irradiance_size = v->irradiance_size, .reuse_texture_space = true};
        if (dm_renderer_create(&a, &d, &v->r_other, err) != DM_OK) return false;
    }
    return dm_render_frame(v->r_other, fo, err) == DM_OK;
}

bool dm_viewer_technique_frame(dm_viewer *v, const dm_frame_options *fo)
{
    dm_error err = {0};
    int w, h;
    dm_renderer_view_size(v->r, &w, &h);
    size_t n = (size_t)w * h;
    float *a = malloc(n * 4 * sizeof *a), *b = malloc(n * 4 * sizeof *b), *rel = malloc(n * sizeof *rel);
    bool ok = a && b && rel;
    if (!ok) dm_viewer_set_status(v, true, "technique split: cannot allocate %dx%d", w, h);
    if (ok && !render_other(v, fo, &err)) {
        dm_viewer_set_status(v, true, "technique split: %s: %s", dm_sss_technique_name(other(v)),
                             err.detail);
        ok = false;
    }
    if (ok && (dm_renderer_read_linear(v->r_other, a, &err) != DM_OK || dm_renderer_read_linear(v->r, b, &err) != DM_OK ||
               dm_refcmp_stats_compute(a, b, w, h, &v->cmp.stats, rel, &err) != DM_OK)) {
        dm_viewer_set_status(v, true, "technique split: %s", err.detail);
        ok = false;
    }
    if (ok) {
        v->cmp.has_stats = true;
        dm_refcmp_stats_text(&v->cmp.stats, DM_REFCMP_FRAME, v->cmp.text, sizeof v->cmp.text);
        dm_refcmp_view view = {.layout = v->cmp.layout, .split = v->cmp.split, .error_scale = v->cmp.error_scale,
                               .margin_right_px = v->show_panel ? 346 : 0, .margin_bottom_px = 24};
        dm_refcmp_compose(a, b, rel, w, h, &v->cmp.stats, &view, v->rgba, v->opt.width, v->opt.height);
    }
    if (!ok) {
        v->tsplit = false;
        v->dirty = true;
    }
    free(a);
    free(b);
    free(rel);
    return ok;
}
