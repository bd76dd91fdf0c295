/* dm_render_targets.c — the frame: render targets (each module adds its own through
 * dmr_color_target), the camera, the mesh bounds, and the surface inputs every shading pass
 * binds. */
#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/dm_math.h"
#include "render/dm_render_internal.h"

void dmr_add_target(dm_renderer *r, const char *name, GLuint fbo, int w, int h, int channels)
{
    assert(r->target_count < MAX_TARGETS);
    target *t = &r->targets[r->target_count++];
    snprintf(t->name, sizeof t->name, "%s", name);
    t->fbo = fbo;
    t->width = w;
    t->height = h;
    t->channels = channels;
}

dm_result dmr_color_target(dm_renderer *r, const char *name, int w, int h, GLenum internal, GLenum wrap,
                              GLuint *tex, GLuint *fbo, dm_error *err)
{
    glGenTextures(1, tex);
    glBindTexture(GL_TEXTURE_2D, *tex);
    glTexImage2D(GL_TEXTURE_2D, 0, (GLint)internal, w, h, 0, GL_RGBA, GL_FLOAT, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, (GLint)wrap);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, (GLint)wrap);
    const float border[4] = {0, 0, 0, 0};
    glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, border);
    glGenFramebuffers(1, fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, *fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, *tex, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return dm_fail(err, DM_ERR_GL, "target %s (%dx%d): framebuffer incomplete", name, w, h);
    dmr_add_target(r, name, *fbo, w, h, 4);
    return dmr_gl_check(name, err);
}

const GLenum dmr_draw_buffers[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                                    GL_COLOR_ATTACHMENT3};

dm_result dmr_gbuffer_targets(dm_renderer *r, const char *prefix, int w, int h, GLuint depth, GLuint tex[4],
                              GLuint *fbo, dm_error *err)
{
    dm_result rc = DM_OK;
    char name[32];
    for (int i = 0; i < 4 && rc == DM_OK; ++i) {
        GLuint own = 0; /* each texture's single-target FBO stays for read-back */
        snprintf(name, sizeof name, "%s%d", prefix, i);
        rc = dmr_color_target(r, name, w, h, GL_RGBA32F, GL_CLAMP_TO_EDGE, &tex[i], i == 0 ? fbo : &own, err);
    }
    if (rc != DM_OK) return rc;
    glBindFramebuffer(GL_FRAMEBUFFER, *fbo);
    for (int i = 1; i < 4; ++i)
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i, GL_TEXTURE_2D, tex[i], 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return dm_fail(err, DM_ERR_GL, "target %s0..3 with depth: framebuffer incomplete", prefix);
    glDrawBuffers(4, dmr_draw_buffers);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    return dmr_gl_check(prefix, err);
}

int dmr_gbuffer_unit(GLuint p)
{
    return glGetUniformLocation(p, "u_level_weight") >= 0 ? UNIT_SRC : UNIT_LEVEL0;
}

void dmr_bind_gbuffer(GLuint p, const GLuint tex[4])
{
    int unit = dmr_gbuffer_unit(p);
    for (int i = 0; i < 4; ++i) dmr_bind(unit + i, GL_TEXTURE_2D, tex[i]);
}

dm_result dmr_make_targets(dm_renderer *r, dm_error *err)
{
    const dm_render_plan *p = &r->plan;
    dm_result rc = dmr_shadow_targets(r, err);
    if (rc == DM_OK && p->texture_space) rc = dmr_tsd_targets(r, err);
    if (rc != DM_OK) return rc;
    /* float32: read_linear and read_view return it at full precision (alpha = coverage) */
    rc = dmr_color_target(r, "screen", r->width, r->height, GL_RGBA32F, GL_CLAMP_TO_EDGE, &r->screen_tex,
                          &r->screen_fbo, err);
    if (rc != DM_OK) return rc;
    r->view_target = r->target_count;
    rc = dmr_color_target(r, "view", 1, 1, GL_RGBA32F, GL_CLAMP_TO_EDGE, &r->view_tex, &r->view_fbo, err);
    if (rc != DM_OK) return rc;
    glGenRenderbuffers(1, &r->screen_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, r->screen_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, r->width, r->height);
    glBindFramebuffer(GL_FRAMEBUFFER, r->screen_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->screen_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return dm_fail(err, DM_ERR_GL, "target screen: framebuffer with depth incomplete");
    if (p->deferred)
        rc = dmr_gbuffer_targets(r, "gbuffer", r->width, r->height, r->screen_depth, r->gbuf_tex, &r->gbuf_fbo, err);
    if (rc == DM_OK && p->screen_space) rc = dmr_ssss_targets(r, err);
    if (rc == DM_OK && p->effects[DM_EFFECT_GLOW]) rc = dmr_glow_targets(r, err);
    if (rc == DM_OK && p->effects[DM_EFFECT_TONEMAP]) rc = dmr_tonemap_targets(r, err);
    return rc;
}

void dmr_screen_clear(const dm_renderer *r, GLbitfield extra)
{
    GLbitfield bits = extra;
    if (dm_render_plan_find(&r->plan, "background") < 0) bits |= GL_COLOR_BUFFER_BIT;
    glClearColor(0, 0, 0, 0);
    if (bits) glClear(bits);
}

void dmr_frame_camera(dm_renderer *r)
{
    const dm_scene *s = &r->scene;
    float view[16], proj[16], d3[3];
    memcpy(r->eye, s->camera_eye, sizeof r->eye);
    dmr_look_at(view, s->camera_eye, s->camera_target, s->camera_up, r->cam_right, r->cam_up, r->cam_fwd);
    dmr_v3_sub(d3, r->center, r->eye);
    float d = sqrtf(dmr_v3_dot(d3, d3)), rad = r->radius;
    float n = fmaxf(d - 2.0f * rad, 0.01f * rad), f = d + 2.0f * rad;
    float aspect = (float)r->width / (float)r->height;
    float fov = (float)(s->fov_y_deg * DM_PI / 180.0);
    dmr_perspective(proj, fov, aspect, n, f);
    dmr_mat_mul(r->view_proj, proj, view);
    float t = tanf(0.5f * fov);
    for (int k = 0; k < 3; ++k) {
        r->cam_right[k] *= t * aspect;
        r->cam_up[k] *= t;
    }
}
void dmr_set_surface_uniforms(const dm_renderer *r, GLuint p)
{
    const dm_scene *s = &r->scene;
    u1f(p, "u_roughness", s->roughness);
    u1f(p, "u_roughness_scale", r->roughness_scale);
    u1f(p, "u_rho_s", s->rho_s);
    glUniform3fv(loc(p, "u_sh"), DM_RENDER_SH_COUNT, &r->env_sh[0][0]);
    u1f(p, "u_env_intensity", s->env_intensity);
    u1f(p, "u_env_rotation", (float)(s->env_rotation_deg * DM_PI / 180.0));
    u1f(p, "u_mix", s->mix);
}
void dmr_bind_surface(const dm_renderer *r)
{
    dmr_bind(UNIT_ALBEDO, GL_TEXTURE_2D, r->tex_albedo ? r->tex_albedo : r->tex_white);
    dmr_bind(UNIT_NORMAL, GL_TEXTURE_2D, r->tex_normal ? r->tex_normal : r->tex_white);
    dmr_bind(UNIT_SPECULAR, GL_TEXTURE_2D, r->tex_spec ? r->tex_spec : r->tex_white);
    dmr_bind(UNIT_ROUGHNESS, GL_TEXTURE_2D, r->tex_rough ? r->tex_rough : r->tex_white);
    dmr_bind(UNIT_BECKMANN, GL_TEXTURE_2D, r->tex_beckmann ? r->tex_beckmann : r->tex_black);
    dmr_bind(UNIT_RHO_DT, GL_TEXTURE_2D, r->tex_rho_dt ? r->tex_rho_dt : r->tex_black);
    dmr_bind(UNIT_ENV_BRDF, GL_TEXTURE_2D, r->tex_env_brdf ? r->tex_env_brdf : r->tex_black);
    for (int k = 0; k < DM_RENDER_ENV_LEVELS_MAX; ++k)
        dmr_bind(UNIT_ENV_LEVEL0 + k, GL_TEXTURE_2D, r->tex_env_level[k] ? r->tex_env_level[k] : r->tex_black);
    for (int k = 0; k < DM_PLAN_MAX_SHADOWS; ++k)
        if (r->shadow_tex[k]) dmr_bind(UNIT_SHADOW + k, GL_TEXTURE_2D, r->shadow_tex[k]);
    if (r->tex_env_array) dmr_bind(UNIT_ENV_ARRAY, GL_TEXTURE_2D_ARRAY, r->tex_env_array);
}

void dmr_mesh_bounds(dm_renderer *r, const float *v, int n)
{
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            float x = v[(size_t)i * DM_VERTEX_FLOATS + c];
            lo[c] = fminf(lo[c], x);
            hi[c] = fmaxf(hi[c], x);
        }
    float rad = 0;
    for (int c = 0; c < 3; ++c) r->center[c] = 0.5f * (lo[c] + hi[c]);
    for (int i = 0; i < n; ++i) {
        float d[3];
        dmr_v3_sub(d, &v[(size_t)i * DM_VERTEX_FLOATS], r->center);
        rad = fmaxf(rad, dmr_v3_dot(d, d));
    }
    r->radius = sqrtf(rad) > 1e-6f ? sqrtf(rad) : 1.0f;
}
