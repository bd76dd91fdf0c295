/* dm_render_env.c — environment lighting's uploads (prefiltered specular levels, as one array
 * texture when they share size and format; the env-BRDF LUT; the background) and the
 * background pass. The SH diffuse and split-sum specular terms are shader code in the passes
 * that shade (irradiance, final, ss_shade). */
#include <math.h>
#include <string.h>

#include "core/dm_math.h"
#include "render/dm_render_internal.h"

static dm_result upload_env_array(dm_renderer *r, const dm_render_assets *a, dm_error *err);

dm_result dmr_env_upload(dm_renderer *r, const dm_render_assets *a, dm_error *err)
{
    dm_result rc = DM_OK;
    const dm_render_plan *p = &r->plan;
#define UP(field, what, mips, filt, dst)                                                                          \
    if (rc == DM_OK && a->field.texels) rc = dmr_upload(&a->field, what, mips, filt, &r->dst, err)
    if (p->env_specular_active) {
        UP(env_brdf, "env_brdf", false, GL_LINEAR, tex_env_brdf);
        for (int k = 0; k < a->env_level_count && rc == DM_OK; ++k) {
            rc = dmr_upload(&a->env_levels[k], "env_levels", false, GL_LINEAR, &r->tex_env_level[k], err);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
        }
        r->env_level_count = a->env_level_count;
        memcpy(r->env_level_m, a->env_level_m, sizeof r->env_level_m);
        if (rc == DM_OK) rc = upload_env_array(r, a, err);
    }
    if (dm_render_plan_find(p, "background") >= 0) {
        UP(env_background, "env_background", false, GL_LINEAR, tex_background);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    }
#undef UP
    return rc;
}

/* The env levels again as one 2D array texture (two fetches per pixel instead of a chain of
 * branches that llvmpipe runs in full), when they share size and format, as a pack's do. */
static dm_result upload_env_array(dm_renderer *r, const dm_render_assets *a, dm_error *err)
{
    const dm_texture *t0 = &a->env_levels[0];
    for (int k = 1; k < a->env_level_count; ++k)
        if (a->env_levels[k].width != t0->width || a->env_levels[k].height != t0->height ||
            a->env_levels[k].format != t0->format)
            return DM_OK; /* the per-level path stays */
    const fmt_gl *f = &dmr_formats[t0->format];
    glGenTextures(1, &r->tex_env_array);
    glBindTexture(GL_TEXTURE_2D_ARRAY, r->tex_env_array);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, (GLint)f->internal, t0->width, t0->height, a->env_level_count, 0, f->format,
                 f->type, NULL);
    for (int k = 0; k < a->env_level_count; ++k)
        glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, k, t0->width, t0->height, 1, f->format, f->type,
                        a->env_levels[k].texels);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return dmr_gl_check("env_levels (array)", err);
}

void dmr_pass_background(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps, (void)opt;
    GLuint p = r->prog[DM_PASS_BACKGROUND];
    dmr_target_begin(r->screen_fbo, r->width, r->height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
    glUseProgram(p);
    glUniform3fv(loc(p, "u_cam_forward"), 1, r->cam_fwd);
    glUniform3fv(loc(p, "u_cam_right"), 1, r->cam_right);
    glUniform3fv(loc(p, "u_cam_up"), 1, r->cam_up);
    u1f(p, "u_env_rotation", (float)(r->scene.env_rotation_deg * DM_PI / 180.0));
    u1f(p, "u_env_intensity", r->scene.env_intensity);
    dmr_bind(UNIT_BACKGROUND, GL_TEXTURE_2D, r->tex_background);
    dmr_draw_fullscreen(r);
    glDepthMask(GL_TRUE);
    glDisable(GL_DEPTH_TEST);
}
