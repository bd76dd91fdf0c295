/* dm_gpu_target.c — render targets and their names (dm_gpu_target.h). */
#include "render/gpu/dm_gpu_target.h"

#include <assert.h>
#include <stdio.h>
#include <string.h>

void dmg_add_target(dmg *g, const char *name, GLuint fbo, int w, int h, int channels)
{
    assert(g->target_count < DMG_MAX_TARGETS);
    dmg_target *t = &g->targets[g->target_count++];
    snprintf(t->name, sizeof t->name, "%s", name);
    t->fbo = fbo;
    t->width = w;
    t->height = h;
    t->channels = channels;
}

int dmg_find_target(const dmg *g, const char *name)
{
    for (int i = 0; i < g->target_count; ++i)
        if (strcmp(g->targets[i].name, name) == 0) return i;
    return -1;
}

dm_result dmg_color_target(dmg *g, const char *name, int w, int h, GLenum internal, GLenum wrap, GLuint *tex,
                           GLuint *fbo, dm_error *err)
{
    *tex = dmg_make(g, DMG_TEXTURE);
    glBindTexture(GL_TEXTURE_2D, *tex);
    glTexImage2D(GL_TEXTURE_2D, 0, (GLint)internal, w, h, 0, GL_RGBA, GL_FLOAT, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, (GLint)wrap);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, (GLint)wrap);
    const float border[4] = {0, 0, 0, 0};
    glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, border);
    *fbo = dmg_make(g, DMG_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, *fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, *tex, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return dm_fail(err, DM_ERR_GL, "target %s (%dx%d): framebuffer incomplete", name, w, h);
    dmg_add_target(g, name, *fbo, w, h, 4);
    return dmg_check(name, err);
}

GLuint dmg_depth_buffer(dmg *g, int w, int h)
{
    GLuint rb = dmg_make(g, DMG_RENDERBUFFER);
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    return rb;
}

dm_result dmg_attach_depth(GLuint fbo, GLuint depth, const char *what, dm_error *err)
{
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return dm_fail(err, DM_ERR_GL, "target %s with depth: framebuffer incomplete", what);
    return DM_OK;
}

const GLenum dmg_draw_buffers[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                                    GL_COLOR_ATTACHMENT3};

dm_result dmg_gbuffer_targets(dmg *g, const char *prefix, int w, int h, GLuint depth, GLuint tex[4], GLuint *fbo,
                              dm_error *err)
{
    dm_result rc = DM_OK;
    char name[32];
    for (int i = 0; i < 4 && rc == DM_OK; ++i) {
        GLuint own = 0; /* each texture's single-target FBO stays for read-back */
        snprintf(name, sizeof name, "%s%d", prefix, i);
        rc = dmg_color_target(g, name, w, h, GL_RGBA32F, GL_CLAMP_TO_EDGE, &tex[i], i == 0 ? fbo : &own, err);
    }
    if (rc != DM_OK) return rc;
    glBindFramebuffer(GL_FRAMEBUFFER, *fbo);
    for (int i = 1; i < 4; ++i)
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i, GL_TEXTURE_2D, tex[i], 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return dm_fail(err, DM_ERR_GL, "target %s0..3 with depth: framebuffer incomplete", prefix);
    glDrawBuffers(4, dmg_draw_buffers);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    return dmg_check(prefix, err);
}
