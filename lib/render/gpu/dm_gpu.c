/* dm_gpu.c — the GL object registry, raw texture uploads and the error check (dm_gpu.h). */
#include "render/gpu/dm_gpu.h"

#include <assert.h>
#include <string.h>

GLuint dmg_make(dmg *g, dmg_kind kind)
{
    assert(g->object_count < DMG_MAX_OBJECTS);
    GLuint name = 0;
    switch (kind) {
    case DMG_TEXTURE: glGenTextures(1, &name); break;
    case DMG_FRAMEBUFFER: glGenFramebuffers(1, &name); break;
    case DMG_RENDERBUFFER: glGenRenderbuffers(1, &name); break;
    case DMG_SAMPLER: glGenSamplers(1, &name); break;
    case DMG_PROGRAM: name = glCreateProgram(); break;
    case DMG_VERTEX_SHADER: name = glCreateShader(GL_VERTEX_SHADER); break;
    case DMG_FRAGMENT_SHADER: name = glCreateShader(GL_FRAGMENT_SHADER); break;
    case DMG_BUFFER: glGenBuffers(1, &name); break;
    case DMG_VERTEX_ARRAY: glGenVertexArrays(1, &name); break;
    case DMG_QUERY: glGenQueries(1, &name); break;
    case DMG_KIND_COUNT: assert(!"not a kind"); break;
    }
    if (name) {
        g->objects[g->object_count].kind = (uint32_t)kind;
        g->objects[g->object_count++].name = name;
    }
    return name;
}

static void delete_one(dmg_kind kind, GLuint name)
{
    switch (kind) {
    case DMG_TEXTURE: glDeleteTextures(1, &name); break;
    case DMG_FRAMEBUFFER: glDeleteFramebuffers(1, &name); break;
    case DMG_RENDERBUFFER: glDeleteRenderbuffers(1, &name); break;
    case DMG_SAMPLER: glDeleteSamplers(1, &name); break;
    case DMG_PROGRAM: glDeleteProgram(name); break;
    case DMG_VERTEX_SHADER:
    case DMG_FRAGMENT_SHADER: glDeleteShader(name); break;
    case DMG_BUFFER: glDeleteBuffers(1, &name); break;
    case DMG_VERTEX_ARRAY: glDeleteVertexArrays(1, &name); break;
    case DMG_QUERY: glDeleteQueries(1, &name); break;
    case DMG_KIND_COUNT: break;
    }
}

void dmg_free(dmg *g, dmg_kind kind, GLuint name)
{
    if (!name) return;
    for (int i = g->object_count - 1; i >= 0; --i)
        if (g->objects[i].kind == (uint32_t)kind && g->objects[i].name == name) {
            delete_one(kind, name);
            memmove(&g->objects[i], &g->objects[i + 1], sizeof g->objects[0] * (size_t)(g->object_count - 1 - i));
            --g->object_count;
            return;
        }
    assert(!"not a recorded object");
}

void dmg_free_all(dmg *g)
{
    for (int i = g->object_count - 1; i >= 0; --i) delete_one((dmg_kind)g->objects[i].kind, g->objects[i].name);
    g->object_count = 0;
    g->target_count = 0;
}

dm_result dmg_check(const char *what, dm_error *err)
{
    GLenum e = glGetError(), first = e;
    while (e != GL_NO_ERROR) e = glGetError();
    if (first != GL_NO_ERROR) return dm_fail(err, DM_ERR_GL, "%s: GL error 0x%04x", what, (unsigned)first);
    return DM_OK;
}

GLuint dmg_texture_2d(dmg *g, int w, int h, GLenum internal, GLenum format, GLenum type, const void *texels,
                      bool mipmaps, GLenum filter)
{
    GLuint tex = dmg_make(g, DMG_TEXTURE);
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, (GLint)internal, w, h, 0, format, type, texels);
    if (mipmaps) glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, mipmaps ? GL_LINEAR_MIPMAP_LINEAR : (GLint)filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, (GLint)filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return tex;
}

GLuint dmg_solid_texture(dmg *g, uint8_t v)
{
    uint8_t px[4] = {v, v, v, 255};
    GLuint tex = dmg_make(g, DMG_TEXTURE);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, px);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return tex;
}
