/* render_into_fbo.c — the dermis skin renderer drawing into a framebuffer object that YOUR
 * code owns, as an engine would embed it (a UI panel, a material preview, a texture).
 *
 *   render_into_fbo PACK.dpk OUT.png [WIDTH HEIGHT]
 *
 * What it shows an engine programmer:
 *   - the renderer never makes a context or a window: you make a GL 3.3+ core context
 *     current (here headless, with dermis's small OSMesa host) and keep it current for
 *     every dm_renderer_* call.
 *   - dm_render_assets_from_pack turns an open pack into the renderer's inputs without
 *     copying (they point into the pack's mapping: keep the pack open while creating).
 *   - the renderer draws into its own targets; dm_renderer_blit_display puts the finished
 *     8-bit sRGB picture into your framebuffer (any rectangle, scaled if needed) and gives
 *     you back your GL_READ/DRAW_FRAMEBUFFER bindings.
 *   - every call returns a dm_result and fills a dm_error whose detail names the problem.
 * Exit codes: 0 done, 1 usage, 2 the pack cannot be read, 3 OpenGL or the renderer failed,
 * 4 the PNG cannot be written.
 */
#define GL_GLEXT_PROTOTYPES 1 /* libOSMesa exports every GL entry point: no loader needed */
#include <GL/glcorearb.h>
#include <stdio.h>
#include <stdlib.h>

#include "pack/dm_pack.h"
#include "core/dm_png.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_pack.h"

/* The caller's side: an FBO with one RGBA8 colour renderbuffer, as an engine might keep for
 * a viewport. (8-bit RGBA, not sRGB: the renderer's bytes are sRGB-encoded already.) */
typedef struct my_target {
    GLuint fbo, color;
    int width, height;
} my_target;

static int my_target_create(my_target *t, int width, int height)
{
    t->width = width, t->height = height;
    glGenRenderbuffers(1, &t->color);
    glBindRenderbuffer(GL_RENDERBUFFER, t->color);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glGenFramebuffers(1, &t->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, t->fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t->color);
    int ok = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return ok;
}

static void my_target_destroy(my_target *t)
{
    glDeleteFramebuffers(1, &t->fbo);
    glDeleteRenderbuffers(1, &t->color);
}

/* One frame of the renderer into the caller's target: create from the pack's assets,
 * render, blit. The renderer is made at the target's size, so the blit is an exact copy;
 * a renderer of another size would be scaled into the rectangle. */
static dm_result render_into(const dm_render_assets *assets, const my_target *t, dm_error *err)
{
    dm_renderer *r = NULL;
    dm_render_desc desc = {.width = t->width, .height = t->height}; /* zero fields: defaults */
    dm_result rc = dm_renderer_create(assets, &desc, &r, err);
    if (rc == DM_OK) rc = dm_render_frame(r, &(dm_frame_options){0}, err); /* the final picture */
    if (rc == DM_OK) rc = dm_renderer_blit_display(r, t->fbo, 0, 0, t->width, t->height, err);
    dm_renderer_destroy(r); /* frees its GL objects: the context must still be current */
    return rc;
}

int main(int argc, char **argv)
{
    if (argc != 3 && argc != 5) {
        fprintf(stderr, "Usage: render_into_fbo PACK.dpk OUT.png [WIDTH HEIGHT]  (default: the scene's size)\n");
        return 1;
    }

    /* 1. The pack (verified whole on open) and the renderer's inputs from it. */
    dm_error err = {0};
    dm_pack pack;
    dm_scene scene;
    dm_profile profile;
    dm_render_assets assets;
    if (dm_pack_open(argv[1], &pack, &err) != DM_OK ||
        dm_render_assets_from_pack(&pack, &scene, &profile, &assets, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_pack_close(&pack);
        return 2;
    }
    int width = argc == 5 ? atoi(argv[3]) : scene.width, height = argc == 5 ? atoi(argv[4]) : scene.height;
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
        fprintf(stderr, "error: size %dx%d, expected 1..16384 per side\n", width, height);
        dm_pack_close(&pack);
        return 1;
    }

    /* 2. A current GL 3.3 core context: yours in an engine; here dermis's OSMesa host. */
    dm_osmesa *ctx = NULL;
    if (dm_osmesa_create(&ctx, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_pack_close(&pack);
        return 3;
    }

    /* 3. Your framebuffer, the renderer's frame in it, and your own read-back. */
    my_target target = {0};
    uint8_t *rgba = malloc((size_t)width * height * 4);
    int status = 0;
    if (!rgba || !my_target_create(&target, width, height)) {
        fprintf(stderr, "error: %s\n", !rgba ? "out of memory" : "the RGBA8 framebuffer is incomplete");
        status = 3;
    } else if (render_into(&assets, &target, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        status = 3;
    } else {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, target.fbo);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        GLenum e = glGetError();
        if (e != GL_NO_ERROR) {
            fprintf(stderr, "error: glReadPixels: GL error 0x%04x\n", (unsigned)e);
            status = 3;
        }
    }

    /* 4. The PNG: glReadPixels rows are bottom-up, as dm_png_write_pixels takes them. */
    if (status == 0 && dm_png_write_pixels(argv[2], width, height, 4, 8, rgba, NULL, NULL, 0, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        status = 4;
    }
    if (status == 0) printf("%s: %dx%d\n", argv[2], width, height);

    /* 5. GL objects before the context, the pack last (the assets pointed into it). */
    if (target.fbo) my_target_destroy(&target);
    free(rgba);
    dm_osmesa_destroy(ctx);
    dm_pack_close(&pack);
    return status;
}
