/* dm_gpu.h — the GL layer: every GL object the renderer makes, made and freed through one
 * registry, plus raw texture uploads and the small binding helpers. Knows nothing of the
 * renderer, the scene or the plan: callers hand in sizes, formats and texels.
 *
 * The registry records each object it makes (textures, framebuffers, renderbuffers, samplers,
 * programs and shaders, buffers, vertex arrays, queries); dmg_free frees one at once (a
 * replaced or transient object), dmg_free_all every one left, newest first. It lives in the
 * caller's memory (zero-initialised: empty) and allocates nothing. Every function needs the
 * GL context current. */
#ifndef DM_GPU_H
#define DM_GPU_H

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#include <stdbool.h>
#include <stdint.h>

#include "core/dm_result.h"

typedef enum dmg_kind {
    DMG_TEXTURE,
    DMG_FRAMEBUFFER,
    DMG_RENDERBUFFER,
    DMG_SAMPLER,
    DMG_PROGRAM,
    DMG_VERTEX_SHADER,
    DMG_FRAGMENT_SHADER,
    DMG_BUFFER,
    DMG_VERTEX_ARRAY,
    DMG_QUERY,
    DMG_KIND_COUNT
} dmg_kind;

/* A named render target: what read-back and the target queries see (channels 1: depth). */
typedef struct dmg_target {
    char name[32];
    GLuint fbo;
    int width, height, channels;
} dmg_target;

enum { DMG_MAX_OBJECTS = 512, DMG_MAX_TARGETS = 32 };

typedef struct dmg {
    struct {
        uint32_t kind;
        GLuint name;
    } objects[DMG_MAX_OBJECTS];
    int object_count;
    dmg_target targets[DMG_MAX_TARGETS]; /* in the order they were made (dmg_add_target) */
    int target_count;
} dmg;

/* A new object of `kind`, recorded (asserts fewer than DMG_MAX_OBJECTS live). */
GLuint dmg_make(dmg *g, dmg_kind kind);
/* Frees one recorded object now (0: nothing). */
void dmg_free(dmg *g, dmg_kind kind, GLuint name);
/* Frees every recorded object, newest first; the registry is empty after. */
void dmg_free_all(dmg *g);

/* DM_ERR_GL naming `what` and the first pending GL error (all are drained), or DM_OK. */
dm_result dmg_check(const char *what, dm_error *err);

/* A w x h 2D texture from texels (NULL: storage only) in GL's (internal, format, type), clamped
 * to edge, `filter` for magnification, and minification too unless mipmaps are made. */
GLuint dmg_texture_2d(dmg *g, int w, int h, GLenum internal, GLenum format, GLenum type, const void *texels,
                      bool mipmaps, GLenum filter);
/* A 1x1 RGBA8 texture (v, v, v, 255), nearest. */
GLuint dmg_solid_texture(dmg *g, uint8_t v);

static inline void dmg_bind(int unit, GLenum target, GLuint tex)
{
    glActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    glBindTexture(target, tex);
}
static inline void dmg_target_begin(GLuint fbo, int w, int h)
{
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, w, h);
}
static inline GLint dmg_loc(GLuint p, const char *name)
{
    return glGetUniformLocation(p, name);
}
static inline void dmg_u1i(GLuint p, const char *n, int v)
{
    glUniform1i(dmg_loc(p, n), v);
}
static inline void dmg_u1f(GLuint p, const char *n, float v)
{
    glUniform1f(dmg_loc(p, n), v);
}
static inline void dmg_u2f(GLuint p, const char *n, float a, float b)
{
    glUniform2f(dmg_loc(p, n), a, b);
}

#endif
