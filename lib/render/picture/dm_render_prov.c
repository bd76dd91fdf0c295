#include "render/dm_render_prov.h"

#include <stdio.h>
#include <string.h>

void dm_render_provenance(dm_provenance *p, const char *tool, const char *source, const char *input_hash,
                          const dm_scene *s, const dm_renderer *r, const char *view, double light_azimuth_deg,
                          int frames)
{
    dm_prov_init(p, tool);
    snprintf(p->input_hash, sizeof p->input_hash, "%s", input_hash);
    int w = s->width, h = s->height, irr = s->irradiance_size;
    if (r) dm_renderer_size(r, &w, &h, &irr);
    dm_prov_add_string(p, "source", source);
    dm_prov_add_string(p, "scene", s->path);
    char fx[256] = "";
    size_t n = 0;
    for (int e = 0; e < DM_EFFECT_COUNT; ++e)
        if (s->effects[e] && n < sizeof fx)
            n += (size_t)snprintf(fx + n, sizeof fx - n, "%s%s", n ? "," : "", dm_effect_name((dm_effect)e));
    dm_prov_add_string(p, "effects", fx);
    dm_prov_add_string(p, "view", view);
    dm_prov_add_int(p, "width", w);
    dm_prov_add_int(p, "height", h);
    dm_prov_add_int(p, "irradiance_size", irr);
    dm_prov_add_int(p, "blur_taps", s->blur_taps);
    if (s->sss_technique != DM_SSS_TEXTURE_SPACE) { /* texture-space outputs keep their metadata as it was */
        dm_prov_add_string(p, "technique", dm_sss_technique_name(s->sss_technique));
        dm_prov_add_int(p, "screen_taps", s->screen_taps);
    }
    if (s->effects[DM_EFFECT_TRANSLUCENCY]) dm_prov_add_double(p, "translucency_intensity", s->translucency_intensity);
    dm_prov_add_string(p, "profile", s->profile.name);
    dm_prov_add_double(p, "mix", s->mix);
    dm_prov_add_double(p, "exposure", s->exposure);
    dm_prov_add_double(p, "light_azimuth_deg", light_azimuth_deg);
    dm_prov_add_int(p, "light_count", s->light_count);
    char cam[160];
    snprintf(cam, sizeof cam, "eye %g %g %g target %g %g %g fov %g", (double)s->camera_eye[0],
             (double)s->camera_eye[1], (double)s->camera_eye[2], (double)s->camera_target[0],
             (double)s->camera_target[1], (double)s->camera_target[2], (double)s->fov_y_deg);
    dm_prov_add_string(p, "camera", cam);
    dm_prov_add_int(p, "frames", frames);
    dm_prov_add_string(p, "renderer", r ? dm_renderer_gl_name(r) : "");
}

void dm_render_settings_provenance(dm_provenance *p, const dm_render_desc *d, const dm_renderer *r)
{
    /* every speed/accuracy setting of dm_render_desc, defaults resolved, so a picture says
     * which path made it */
    dm_prov_add_int(p, "shadow_pcf_taps", d->shadow_pcf_taps ? d->shadow_pcf_taps : 4);
    dm_prov_add_int(p, "shadow_size", d->shadow_size ? d->shadow_size : DM_RENDER_SHADOW_SIZE_DEFAULT);
    dm_prov_add_int(p, "blur_reduce_from", d->blur_reduce_from);
    dm_prov_add_int(p, "blur_reduce_shift", d->blur_reduce_from ? (d->blur_reduce_shift ? d->blur_reduce_shift : 1) : 0);
    if (r && dm_renderer_plan(r)->view == DM_VIEW_SPECULAR) dm_prov_add_double(p, "view_gain", dm_renderer_view_gain(r));
    float lo, hi;
    const char *quantity = NULL;
    if (r) dm_renderer_view_scale(r, &lo, &hi, &quantity);
    if (quantity) {
        dm_prov_add_string(p, "colour_scale", quantity);
        dm_prov_add_double(p, "colour_scale_lo", lo);
        dm_prov_add_double(p, "colour_scale_hi", hi);
    }
    dm_prov_add_string(p, "blur_resolution",
                       d->blur_auto_resolution ? "auto" : d->blur_reduce_from ? "reduce_from" : "full");
    char sizes[96] = "", *end = sizes; /* each level's texels per side as rendered */
    for (int i = 0; r && i < dm_renderer_target_count(r); ++i) {
        dm_target_info ti;
        dm_renderer_target_info(r, i, &ti);
        bool level = !strcmp(ti.name, "irradiance") || (!strncmp(ti.name, "blur", 4) && ti.name[4] >= '1' &&
                                                        ti.name[4] <= '9' && !ti.name[5]);
        if (level && end < sizes + sizeof sizes - 8)
            end += snprintf(end, (size_t)(sizes + sizeof sizes - end), "%s%d", end > sizes ? " " : "", ti.width);
    }
    if (*sizes) dm_prov_add_string(p, "blur_level_sizes", sizes);
    dm_prov_add_int(p, "blur_half_float", d->blur_half_float ? 1 : 0);
    if (r && dm_renderer_plan(r)->blur_levels > 1) /* where the blur ran: the same to float rounding */
        dm_prov_add_string(p, "blur_on", dm_renderer_blur_on_cpu(r) ? "cpu" : "gl");
    if (r && dm_renderer_plan(r)->texture_space) /* where the levels are summed: the diffusion pass's target */
        dm_prov_add_string(p, "diffusion_sum", dm_renderer_find_target(r, "diffusion") >= 0 ? "per_texel" : "per_pixel");
    dm_prov_add_int(p, "reuse_texture_space", d->reuse_texture_space ? 1 : 0);
}
