/* dm_render_shadow.c — lights and shadows: per-frame light positions and colours (turned by the
 * light rotation), a depth map per casting light (orthographic for directional lights around
 * the mesh's bounding sphere, perspective for point lights), the light uniforms every shading
 * pass reads, and the shadow pass itself. PCF filtering is in shaders/common.glsl. */
#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/dm_math.h"
#include "render/dm_render_internal.h"

dm_result dmr_shadow_targets(dm_renderer *r, dm_error *err)
{
    const dm_render_plan *p = &r->plan;
    char name[32];
    /* separate 2D depth textures, not one array: llvmpipe's sampler2DArrayShadow path
     * measured ~4x slower per tap than sampler2DShadow */
    for (int i = 0; i < p->shadow_count; ++i) {
        glGenTextures(1, &r->shadow_tex[i]);
        glBindTexture(GL_TEXTURE_2D, r->shadow_tex[i]);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, r->shadow_edge, r->shadow_edge, 0, GL_DEPTH_COMPONENT,
                     GL_FLOAT, NULL);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
        glGenFramebuffers(1, &r->shadow_fbo[i]);
        glBindFramebuffer(GL_FRAMEBUFFER, r->shadow_fbo[i]);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, r->shadow_tex[i], 0);
        glDrawBuffer(GL_NONE);
        glReadBuffer(GL_NONE);
        snprintf(name, sizeof name, "shadow%d", i);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            return dm_fail(err, DM_ERR_GL, "target %s: framebuffer incomplete", name);
        dmr_add_target(r, name, r->shadow_fbo[i], r->shadow_edge, r->shadow_edge, 1);
    }
    return DM_OK;
}

void dmr_frame_lights(dm_renderer *r, float rotation_deg)
{
    const dm_scene *s = &r->scene;
    float a = (float)(rotation_deg * DM_PI / 180.0), c = cosf(a), sn = sinf(a);
    for (int i = 0; i < s->light_count; ++i) {
        const dm_light *l = &s->lights[i];
        const float *v = l->type == DM_LIGHT_DIRECTIONAL ? l->direction : l->position;
        float x = c * v[0] + sn * v[2], z = -sn * v[0] + c * v[2];
        r->light_pos[i][0] = x;
        r->light_pos[i][1] = v[1];
        r->light_pos[i][2] = z;
        r->light_pos[i][3] = l->type == DM_LIGHT_DIRECTIONAL ? 0.0f : 1.0f;
        if (l->type == DM_LIGHT_DIRECTIONAL) dmr_v3_norm(r->light_pos[i]);
        for (int k = 0; k < 3; ++k) r->light_color[i][k] = l->color[k] * l->intensity;
    }
    for (int j = 0; j < r->plan.shadow_count; ++j) {
        int i = r->plan.shadow_light[j];
        float view[16], proj[16], eye[3], up[3] = {0, 1, 0};
        float rad = r->radius;
        if (r->light_pos[i][3] == 0.0f) {
            for (int k = 0; k < 3; ++k) eye[k] = r->center[k] + r->light_pos[i][k] * 2.0f * rad;
            dmr_look_at(view, eye, r->center, up, NULL, NULL, NULL);
            dmr_ortho(proj, rad * 1.02f, 0.5f * rad, 3.5f * rad);
            r->light_depth[i][0] = 0.5f * rad, r->light_depth[i][1] = 3.5f * rad, r->light_depth[i][2] = 1.0f;
        } else {
            float d3[3];
            memcpy(eye, r->light_pos[i], sizeof eye);
            dmr_v3_sub(d3, r->center, eye);
            float d = sqrtf(dmr_v3_dot(d3, d3));
            float n = d > rad * 1.01f ? fmaxf(d - rad, 0.01f * rad) * 0.9f : 0.01f * rad, f = d + rad * 1.1f;
            if (d > rad * 1.01f)
                dmr_perspective(proj, 2.0f * asinf(rad / d) * 1.05f, 1.0f, n, f);
            else
                dmr_perspective(proj, (float)(150.0 * DM_PI / 180.0), 1.0f, n, f);
            r->light_depth[i][0] = n, r->light_depth[i][1] = f, r->light_depth[i][2] = 0.0f;
            dmr_look_at(view, eye, r->center, up, NULL, NULL, NULL);
        }
        dmr_mat_mul(r->light_matrix[i], proj, view);
    }
}

void dmr_set_light_uniforms(const dm_renderer *r, GLuint p)
{
    const dm_scene *s = &r->scene;
    glUniform4fv(loc(p, "u_light_pos"), s->light_count, &r->light_pos[0][0]);
    glUniform3fv(loc(p, "u_light_color"), s->light_count, &r->light_color[0][0]);
    glUniformMatrix4fv(loc(p, "u_light_matrix"), s->light_count, GL_FALSE, &r->light_matrix[0][0]);
    u1f(p, "u_shadow_normal_offset", 3.0f * r->radius / (float)r->shadow_edge);
    u1f(p, "u_shadow_texel", 1.0f / (float)r->shadow_edge);
}

void dmr_pass_shadow(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)opt;
    int j = ps->index;
    int i = r->plan.shadow_light[j];
    GLuint p = r->prog[DM_PASS_SHADOW];
    dmr_target_begin(r->shadow_fbo[j], r->shadow_edge, r->shadow_edge);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.5f, 4.0f);
    glUseProgram(p);
    glUniformMatrix4fv(loc(p, "u_matrix"), 1, GL_FALSE, r->light_matrix[i]);
    dmr_draw_mesh(r);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_DEPTH_TEST);
}
