/* dm_render_readback.c — the frame's outputs back to the CPU: any target as float, the linear
 * screen, the last view at full precision, the 8-bit display; the display blitted into the
 * caller's framebuffer; plan and size queries. */
#include <assert.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/dm_render_internal.h"
#include "render/gpu/dm_gpu_target.h"

const dm_render_plan *dm_renderer_plan(const dm_renderer *r)
{
    return &r->f.plan;
}

void dm_renderer_size(const dm_renderer *r, int *width, int *height, int *irradiance_size)
{
    if (width) *width = r->f.width;
    if (height) *height = r->f.height;
    if (irradiance_size) *irradiance_size = r->f.irr_edge;
}

int dm_renderer_target_count(const dm_renderer *r)
{
    return r->f.gpu.target_count;
}

void dm_renderer_target_info(const dm_renderer *r, int index, dm_target_info *info)
{
    assert(index >= 0 && index < r->f.gpu.target_count);
    const dmg_target *t = &r->f.gpu.targets[index];
    info->name = t->name;
    info->width = t->width;
    info->height = t->height;
    info->channels = t->channels;
}

int dm_renderer_find_target(const dm_renderer *r, const char *name)
{
    return dmg_find_target(&r->f.gpu, name);
}

dm_result dm_renderer_read_target(dm_renderer *r, int index, float *out, dm_error *err)
{
    assert(index >= 0 && index < r->f.gpu.target_count);
    const dmg_target *t = &r->f.gpu.targets[index];
    if (t->fbo == r->f.screen_fbo) dmr_glow_settle(r); /* the linear picture holds the glow */
    for (int k = 1; k < DM_PROFILE_MAX_GAUSSIANS; ++k) /* a level whose upload waits */
        if (t->fbo && t->fbo == r->f.level_fbo[k]) dmr_levels_need(&r->f, 1u << k);
    glBindFramebuffer(GL_FRAMEBUFFER, t->fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (t->channels == 1) {
        glReadPixels(0, 0, t->width, t->height, GL_DEPTH_COMPONENT, GL_FLOAT, out);
    } else {
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glReadPixels(0, 0, t->width, t->height, GL_RGBA, GL_FLOAT, out);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return dmg_check(t->name, err);
}

dm_result dm_renderer_read_linear(dm_renderer *r, float *rgba, dm_error *err)
{
    return dm_renderer_read_target(r, dm_renderer_find_target(r, "screen"), rgba, err);
}

void dm_renderer_view_size(const dm_renderer *r, int *width, int *height)
{
    const dmg_target *t = &r->f.gpu.targets[r->f.view_in_target ? r->f.view_target : dm_renderer_find_target(r, "screen")];
    *width = t->width;
    *height = t->height;
}

dm_result dm_renderer_read_view(dm_renderer *r, float *rgba, dm_error *err)
{
    return dm_renderer_read_target(r, r->f.view_in_target ? r->f.view_target : dm_renderer_find_target(r, "screen"), rgba,
                                   err);
}

static uint8_t dmr_srgb8(float c)
{
    c = c > 0 ? (c < 1 ? c : 1) : 0; /* NaN becomes 0 */
    float e = c <= 0.0031308f ? 12.92f * c : 1.055f * powf(c, 1.0f / 2.4f) - 0.055f;
    return (uint8_t)lrintf(e * 255.0f);
}

dm_result dm_renderer_read_display(dm_renderer *r, uint8_t *rgba, dm_error *err)
{
    if (r->tonemapped) {
        glBindFramebuffer(GL_FRAMEBUFFER, r->tonemap.display_fbo);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glReadPixels(0, 0, r->f.width, r->f.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        return dmg_check("display", err);
    }
    size_t n = (size_t)r->f.width * r->f.height;
    float *lin = malloc(n * 4 * sizeof *lin);
    if (!lin) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "display: cannot allocate %zu floats", n * 4);
    dm_result rc = dm_renderer_read_linear(r, lin, err);
    for (size_t i = 0; rc == DM_OK && i < n; ++i) {
        for (int c = 0; c < 3; ++c) rgba[i * 4 + c] = dmr_srgb8(lin[i * 4 + c]);
        rgba[i * 4 + 3] = 255;
    }
    free(lin);
    return rc;
}

/* The display built on the CPU (dm_renderer_read_display) in the renderer's own RGBA8
 * texture and its framebuffer, made on first use at the output size (fixed at create). */
static dm_result display_upload(dm_renderer *r, dm_error *err)
{
    size_t size = (size_t)r->f.width * r->f.height * 4;
    uint8_t *rgba = malloc(size);
    if (!rgba) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "blit_display: cannot allocate %zu bytes", size);
    dm_result rc = dm_renderer_read_display(r, rgba, err);
    if (rc == DM_OK && !r->blit_fbo) {
        r->blit_tex = dmg_make(&r->f.gpu, DMG_TEXTURE);
        glBindTexture(GL_TEXTURE_2D, r->blit_tex);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, r->f.width, r->f.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST); /* no mip levels */
        r->blit_fbo = dmg_make(&r->f.gpu, DMG_FRAMEBUFFER);
        glBindFramebuffer(GL_FRAMEBUFFER, r->blit_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, r->blit_tex, 0);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            rc = dm_fail(err, DM_ERR_GL, "blit_display: its %dx%d RGBA8 framebuffer is incomplete", r->f.width,
                         r->f.height);
    }
    if (rc == DM_OK) {
        glBindTexture(GL_TEXTURE_2D, r->blit_tex);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, r->f.width, r->f.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
        rc = dmg_check("blit_display upload", err);
    }
    free(rgba);
    return rc;
}

dm_result dm_renderer_blit_display(dm_renderer *r, unsigned int framebuffer, int x, int y, int width, int height,
                                   dm_error *err)
{
    assert(r);
    if (width < 1 || height < 1)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "blit_display: %s %d, expected >= 1",
                       width < 1 ? "width" : "height", width < 1 ? width : height);
    if ((x > 0 && width > INT_MAX - x) || (y > 0 && height > INT_MAX - y))
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "blit_display: rectangle %dx%d at (%d, %d) ends past INT_MAX",
                       width, height, x, y);
    if (!r->has_frame)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT,
                       "blit_display: no frame rendered yet (call dm_render_frame first)");
    if (framebuffer != 0 && !glIsFramebuffer(framebuffer))
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "blit_display: %u is not a framebuffer object", framebuffer);
    glGetError(); /* a stale error of the caller's is not this call's */
    GLint read_fbo = 0, draw_fbo = 0;
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_fbo);
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_fbo);
    GLboolean scissor = glIsEnabled(GL_SCISSOR_TEST), srgb = glIsEnabled(GL_FRAMEBUFFER_SRGB);

    dm_result rc = r->tonemapped ? DM_OK : display_upload(r, err);
    if (rc == DM_OK) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, r->tonemapped ? r->tonemap.display_fbo : r->blit_fbo);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
        GLenum status = glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE)
            rc = dm_fail(err, DM_ERR_INVALID_ARGUMENT, "blit_display: framebuffer %u is incomplete (status 0x%04x)",
                         framebuffer, (unsigned)status);
    }
    if (rc == DM_OK) {
        /* a blit obeys these two: the bytes land as they are, in the whole rectangle */
        glDisable(GL_SCISSOR_TEST);
        glDisable(GL_FRAMEBUFFER_SRGB);
        bool same = width == r->f.width && height == r->f.height;
        glBlitFramebuffer(0, 0, r->f.width, r->f.height, x, y, x + width, y + height, GL_COLOR_BUFFER_BIT,
                          same ? GL_NEAREST : GL_LINEAR);
        rc = dmg_check("blit_display", err);
    }
    if (scissor) glEnable(GL_SCISSOR_TEST);
    if (srgb) glEnable(GL_FRAMEBUFFER_SRGB);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)read_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)draw_fbo);
    return rc;
}
