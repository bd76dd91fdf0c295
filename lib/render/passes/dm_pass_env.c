/* dm_pass_env.c — environment lighting's checks and uploads (prefiltered specular levels, as
 * one array texture when they share size and format; the env-BRDF LUT; the background) and
 * the background pass. The SH diffuse and split-sum specular terms are shader code in the
 * passes that shade (irradiance, final, ss_shade). */
#include <math.h>
#include <string.h>

#include "core/dm_math.h"
#include "render/passes/dm_pass_env.h"

dm_result dmr_env_check(const dmr_frame *f, const dm_render_assets *a, dm_error *err)
{
    const dm_render_plan *p = &f->plan;
    dm_result rc = DM_OK;
    if (p->effects[DM_EFFECT_ENVIRONMENT_LIGHTING] && !a->has_env_sh)
        rc = dm_fail(err, DM_ERR_MISMATCH, "assets: the environment SH is missing, and environment_lighting needs it");
    if (rc == DM_OK && p->env_specular_active) {
        if (a->env_level_count < 1 || a->env_level_count > DM_RENDER_ENV_LEVELS_MAX)
            return dm_fail(err, DM_ERR_MISMATCH,
                           "assets: %d prefiltered environment levels, environment_lighting with specular needs 1..%d",
                           a->env_level_count, DM_RENDER_ENV_LEVELS_MAX);
        for (int k = 0; k < a->env_level_count && rc == DM_OK; ++k) {
            rc = dmr_need_texture(&a->env_levels[k], "a prefiltered environment level", "environment_lighting", err);
            if (rc == DM_OK && k > 0 && !(a->env_level_m[k] > a->env_level_m[k - 1]))
                rc = dm_fail(err, DM_ERR_RANGE, "assets: env_level_m[%d] = %g, expected more than env_level_m[%d] = %g",
                             k, (double)a->env_level_m[k], k - 1, (double)a->env_level_m[k - 1]);
        }
        if (rc == DM_OK) rc = dmr_need_texture(&a->env_brdf, "the env-BRDF LUT", "environment_lighting", err);
    }
    if (rc == DM_OK && dm_render_plan_find(p, "background") >= 0)
        rc = dmr_need_texture(&a->env_background, "the environment background", "environment_lighting", err);
    return rc;
}

/* The env levels again as one 2D array texture (two fetches per pixel instead of a chain of
 * branches that llvmpipe runs in full), when they share size and format, as a pack's do. */
static dm_result upload_env_array(dmr_frame *f, const dm_render_assets *a, dm_error *err)
{
    const dm_texture *t0 = &a->env_levels[0];
    for (int k = 1; k < a->env_level_count; ++k)
        if (a->env_levels[k].width != t0->width || a->env_levels[k].height != t0->height ||
            a->env_levels[k].format != t0->format)
            return DM_OK; /* the per-level path stays */
    GLenum internal, format, type;
    dmr_format_gl(t0->format, &internal, &format, &type);
    f->tex_env_array = dmg_make(&f->gpu, DMG_TEXTURE);
    glBindTexture(GL_TEXTURE_2D_ARRAY, f->tex_env_array);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, (GLint)internal, t0->width, t0->height, a->env_level_count, 0, format, type,
                 NULL);
    for (int k = 0; k < a->env_level_count; ++k)
        glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, k, t0->width, t0->height, 1, format, type,
                        a->env_levels[k].texels);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return dmg_check("env_levels (array)", err);
}

dm_result dmr_env_upload(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err)
{
    dmr_env *e = st;
    dm_result rc = DM_OK;
    const dm_render_plan *p = &f->plan;
    if (p->env_specular_active) {
        if (a->env_brdf.texels) rc = dmr_upload(f, &a->env_brdf, "env_brdf", false, GL_LINEAR, &f->tex_env_brdf, err);
        for (int k = 0; k < a->env_level_count && rc == DM_OK; ++k) {
            rc = dmr_upload(f, &a->env_levels[k], "env_levels", false, GL_LINEAR, &f->tex_env_level[k], err);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
        }
        f->env_level_count = a->env_level_count;
        memcpy(f->env_level_m, a->env_level_m, sizeof f->env_level_m);
        if (rc == DM_OK) rc = upload_env_array(f, a, err);
    }
    if (rc == DM_OK && a->env_background.texels && dm_render_plan_find(p, "background") >= 0) {
        rc = dmr_upload(f, &a->env_background, "env_background", false, GL_LINEAR, &e->background, err);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    }
    return rc;
}

bool dmr_background_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    (void)st, (void)ps;
    *out = (dmr_output){f->screen_fbo, f->width, f->height, 0};
    return true;
}

void dmr_background_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps, (void)opt;
    GLuint p = f->prog[DM_PASS_BACKGROUND];
    glUniform3fv(dmg_loc(p, "u_cam_forward"), 1, f->cam_fwd);
    glUniform3fv(dmg_loc(p, "u_cam_right"), 1, f->cam_right);
    glUniform3fv(dmg_loc(p, "u_cam_up"), 1, f->cam_up);
    dmg_u1f(p, "u_env_rotation", (float)(f->scene.env_rotation_deg * DM_PI / 180.0));
    dmg_u1f(p, "u_env_intensity", f->scene.env_intensity);
    dmg_bind(UNIT_BACKGROUND, GL_TEXTURE_2D, ((const dmr_env *)st)->background);
    dmr_draw_fullscreen(f);
}
