/* dm_render_blur_cpu.c — the texture-space blur passes on the CPU (core/dm_level_blur.h) when
 * OpenGL itself runs on the CPU (llvmpipe, softpipe): there a bilinear RGBA32F fetch costs
 * ~5 CPU ms per tap over the 1024² atlas, several times what plain C pays for the same two
 * texels (docs/render-quality.md). The plan keeps its blur_u k, blur_v k passes (timings,
 * --explain); each runs here instead of blur.glsl: U reads level k−1 (level 0 read back from
 * the irradiance target; later levels kept from the V pass before), V uploads level k into its
 * texture, where the views read it as ever. Each level is also added to the diffusion pass's
 * sum as it is made (core/dm_level_sum.h), and the diffusion pass
 * uploads that sum instead of reading the levels in GL; then nothing in the frame reads levels
 * 1.. in GL, and their uploads (1–2 ms each) wait until something does: a blur view, a
 * read-back of their targets (dmr_blur_cpu_sync runs the chain again from the irradiance
 * target, uploading). The same sums as the shaders, equal to float rounding
 * (tests/render/test_render_blur_cpu.c). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_level_blur.h"
#include "core/dm_level_sum.h"
#include "render/dm_render_internal.h"

static int stretch_index(const dm_renderer *r, int k)
{
    return k - 1 < r->stretch_count - 1 ? k - 1 : r->stretch_count - 1;
}

/* Its buffers and each pass's stretch per texel; false when out of memory. */
static bool allocate(dm_renderer *r, const dm_render_assets *a)
{
    /* three buffers in turn: level k−1, the U pass's result, level k */
    size_t floats = dm_level_blur_floats(r->irr_edge, r->irr_edge);
    for (int i = 0; i < 3; ++i)
        if (!(r->cpu_buf[i] = malloc(sizeof(float) * floats))) return false;
    /* each pass's stretch at its texels, sampled once: the stretch never changes */
    float *st = NULL;
    for (int k = 1; k < r->plan.blur_levels; ++k) {
        const dm_texture *t = &a->stretch[stretch_index(r, k)];
        size_t n = (size_t)t->width * (size_t)t->height;
        float *grow = realloc(st, sizeof *st * 2 * n);
        if (!grow) break;
        st = grow;
        for (size_t i = 0; i < 2 * n; ++i) st[i] = dmr_stretch_value(t, i);
        int w = r->level_edge[k], h = r->level_edge[k - 1];
        r->cpu_step[k][0] = malloc(sizeof(float) * (size_t)w * (size_t)h);
        r->cpu_step[k][1] = malloc(sizeof(float) * (size_t)w * (size_t)w);
        if (!r->cpu_step[k][0] || !r->cpu_step[k][1]) break;
        dm_level_blur_step(st, t->width, t->height, w, h, false, r->cpu_step[k][0]);
        dm_level_blur_step(st, t->width, t->height, w, w, true, r->cpu_step[k][1]);
    }
    free(st);
    for (int k = 1; k < r->plan.blur_levels; ++k)
        if (!r->cpu_step[k][0] || !r->cpu_step[k][1]) return false;
    /* the diffusion pass's sum */
    if (r->diffusion_sum && !(r->cpu_sum = malloc(sizeof(float) * 4 * (size_t)r->irr_edge * (size_t)r->irr_edge)))
        return false;
    return true;
}

/* Adds level k (at cpu_level) to the diffusion pass's sum when this frame's plan sums them. */
static void add_to_sum(dm_renderer *r, int k)
{
    if (!r->cpu_sum || r->cpu_sum_level != k - 1) return;
    int n = r->irr_edge; /* every level at this size (diffusion_sum) */
    dm_level_sum_add(&(dm_level_sum_pass){r->cpu_sum, r->cpu_level, dm_level_blur_stride(n), n,
                                          {r->level_weight[k][0], r->level_weight[k][1], r->level_weight[k][2]},
                                          k == 0, k == r->plan.blur_levels - 1, 0});
    r->cpu_sum_level = k;
}

/* The levels' textures brought up to the chain's state: the chain again from the irradiance
 * target (which a frame reusing texture space keeps), every level uploaded. */
void dmr_blur_cpu_sync(dm_renderer *r)
{
    if (!r->blur_cpu || !r->levels_stale) return;
    r->cpu_syncing = true;
    for (int k = 1; k < r->profile.count; ++k) {
        dmr_blur_cpu_pass(r, &(dm_pass){.kind = DM_PASS_BLUR_U, .index = k});
        dmr_blur_cpu_pass(r, &(dm_pass){.kind = DM_PASS_BLUR_V, .index = k});
    }
    r->cpu_syncing = false;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

bool dmr_blur_cpu_diffusion(dm_renderer *r)
{
    if (!r->cpu_sum || r->cpu_sum_level != r->plan.blur_levels - 1) return false;
    glBindTexture(GL_TEXTURE_2D, r->diff_tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, r->irr_edge, r->irr_edge, GL_RGBA, GL_FLOAT, r->cpu_sum);
    r->cpu_sum_level = -1;
    return true;
}

dm_result dmr_blur_cpu_setup(dm_renderer *r, const dm_render_assets *a, dm_error *err)
{
    dm_blur_path path = r->desc.blur_path;
    if (path < DM_BLUR_PATH_AUTO || path > DM_BLUR_PATH_CPU)
        return dm_fail(err, DM_ERR_RANGE, "renderer: blur_path %d, expected auto (0), gl (1) or cpu (2)", (int)path);
    if (path == DM_BLUR_PATH_CPU && r->level_format != GL_RGBA32F)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT,
                       "renderer: the blur on the CPU keeps float levels: it does not take blur_half_float");
    r->blur_cpu = r->plan.texture_space && r->level_format == GL_RGBA32F && dmr_blur_cpu_wanted(&r->desc, r->timing_cpu);
    if (!r->blur_cpu) return DM_OK;
    if (allocate(r, a)) {
        r->cpu_held = r->cpu_tmp_level = r->cpu_sum_level = -1;
        return DM_OK;
    }
    /* out of memory (three level-sized buffers, two stretch floats a texel a level, the sum): auto
     * keeps the blur in GL, cpu says so */
    size_t mb = (dm_level_blur_floats(r->irr_edge, r->irr_edge) * 4 * 3 +
                 (size_t)r->irr_edge * (size_t)r->irr_edge * (8 * (size_t)(r->plan.blur_levels - 1) + 16)) >> 20;
    dmr_blur_cpu_free(r);
    r->blur_cpu = false;
    if (path == DM_BLUR_PATH_AUTO) return DM_OK;
    return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "renderer: the blur on the CPU needs %zu MB more", mb);
}

bool dm_renderer_blur_on_cpu(const dm_renderer *r)
{
    return r && r->blur_cpu;
}

void dmr_blur_cpu_free(dm_renderer *r)
{
    for (int i = 0; i < 3; ++i) free(r->cpu_buf[i]), r->cpu_buf[i] = NULL;
    free(r->cpu_sum), r->cpu_sum = NULL;
    for (int k = 0; k < DM_PROFILE_MAX_GAUSSIANS; ++k)
        free(r->cpu_step[k][0]), free(r->cpu_step[k][1]), r->cpu_step[k][0] = r->cpu_step[k][1] = NULL;
}

void dmr_blur_cpu_pass(dm_renderer *r, const dm_pass *ps)
{
    int k = ps->index;
    int n = r->level_edge[k], h = r->level_edge[k - 1];
    if (ps->kind == DM_PASS_BLUR_U) {
        /* level k−1 into cpu_buf[0] (the V pass before left it there; level 0, the irradiance
         * pass's, is read back every time), the U result into cpu_buf[1] (n × h) */
        if (k == 1 || r->cpu_held != k - 1) {
            r->cpu_level = dm_level_blur_frame(r->cpu_buf[0], h, h);
            glBindFramebuffer(GL_READ_FRAMEBUFFER, r->irr_fbo[k - 1]);
            glReadBuffer(GL_COLOR_ATTACHMENT0);
            glPixelStorei(GL_PACK_ALIGNMENT, 4);
            glPixelStorei(GL_PACK_ROW_LENGTH, (GLint)(dm_level_blur_stride(h) / 4));
            glReadPixels(0, 0, h, h, GL_RGBA, GL_FLOAT, r->cpu_level);
            glPixelStorei(GL_PACK_ROW_LENGTH, 0);
            r->cpu_held = k - 1;
        }
        if (k == 1) {
            r->cpu_summing = r->cpu_sum && dm_render_plan_find(&r->plan, "diffusion") >= 0 && !r->cpu_syncing;
            r->cpu_sum_level = r->cpu_summing ? -1 : -2;
            add_to_sum(r, 0);
        }
        r->cpu_tmp = dm_level_blur_frame(r->cpu_buf[1], n, h);
        dm_level_blur(&(dm_level_blur_pass){r->cpu_level, h, h, r->cpu_tmp, n, h, false, r->cpu_step[k][0],
                                            r->blur_offset[k], r->blur_weight, r->taps, 0});
        r->cpu_tmp_level = k;
        return;
    }
    if (r->cpu_tmp_level != k) return; /* V without its U: not in any plan */
    float *level = dm_level_blur_frame(r->cpu_buf[2], n, n);
    dm_level_blur(&(dm_level_blur_pass){r->cpu_tmp, n, h, level, n, n, true, r->cpu_step[k][1], r->blur_offset[k],
                                        r->blur_weight, r->taps, 0});
    if (r->cpu_summing) {
        r->levels_stale |= 1u << k;
    } else {
        glBindTexture(GL_TEXTURE_2D, r->irr_tex[k]);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, (GLint)(dm_level_blur_stride(n) / 4));
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, n, n, GL_RGBA, GL_FLOAT, level);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
        r->levels_stale &= ~(1u << k);
    }
    /* level k is the next U pass's input: its buffer becomes cpu_buf[0] */
    float *t = r->cpu_buf[0];
    r->cpu_buf[0] = r->cpu_buf[2], r->cpu_buf[2] = t;
    r->cpu_level = level, r->cpu_held = k, r->cpu_tmp_level = 0;
    add_to_sum(r, k);
}
