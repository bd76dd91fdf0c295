/* dm_pass_shadow.c — the shadow pass: the mesh's depth from each casting light (the matrices
 * are the frame's, dm_frame_scene.c), polygon offset against acne. PCF filtering is in
 * shaders/common.glsl. */
#include <stdio.h>

#include "render/gpu/dm_gpu_target.h"
#include "render/passes/dm_pass_shadow.h"

dm_result dmr_shadow_targets(dmr_frame *f, void *st, dm_error *err)
{
    dmr_shadow *s = st;
    char name[32];
    /* separate 2D depth textures, not one array: llvmpipe's sampler2DArrayShadow path
     * measured ~4x slower per tap than sampler2DShadow */
    for (int i = 0; i < f->plan.shadow_count; ++i) {
        GLuint tex = f->shadow_tex[i] = dmg_make(&f->gpu, DMG_TEXTURE);
        glBindTexture(GL_TEXTURE_2D, tex);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, f->shadow_edge, f->shadow_edge, 0, GL_DEPTH_COMPONENT,
                     GL_FLOAT, NULL);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
        s->fbo[i] = dmg_make(&f->gpu, DMG_FRAMEBUFFER);
        glBindFramebuffer(GL_FRAMEBUFFER, s->fbo[i]);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, tex, 0);
        glDrawBuffer(GL_NONE);
        glReadBuffer(GL_NONE);
        snprintf(name, sizeof name, "shadow%d", i);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            return dm_fail(err, DM_ERR_GL, "target %s: framebuffer incomplete", name);
        dmg_add_target(&f->gpu, name, s->fbo[i], f->shadow_edge, f->shadow_edge, 1);
    }
    return DM_OK;
}

bool dmr_shadow_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    const dmr_shadow *s = st;
    *out = (dmr_output){s->fbo[ps->index], f->shadow_edge, f->shadow_edge, 0};
    return true;
}

void dmr_shadow_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)st, (void)opt;
    GLuint p = f->prog[DM_PASS_SHADOW];
    glUniformMatrix4fv(dmg_loc(p, "u_matrix"), 1, GL_FALSE, f->light_matrix[f->plan.shadow_light[ps->index]]);
    dmr_draw_mesh(f);
}
