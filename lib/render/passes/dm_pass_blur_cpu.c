/* dm_pass_blur_cpu.c — the texture-space blur passes on the CPU (core/dm_level_blur.h) when
 * OpenGL itself runs on the CPU (llvmpipe, softpipe): there a bilinear RGBA32F fetch costs
 * ~5 CPU ms per tap over the 1024² atlas, several times what plain C pays for the same two
 * texels (docs/render-quality.md). The plan keeps its blur_u k, blur_v k passes (timings,
 * --explain); each runs here instead of blur.glsl: U reads level k−1 (level 0 read back from
 * the irradiance target; later levels kept from the V pass before), V uploads level k into its
 * texture, where the views read it as ever. Each level is also added to the diffusion pass's
 * sum as it is made (core/dm_level_sum.h), and the diffusion pass
 * uploads that sum instead of reading the levels in GL; then nothing in the frame reads levels
 * 1.. in GL, and their uploads (1–2 ms each) wait until something does: a blur view, a
 * read-back of their targets (the levels' sync it publishes runs the chain again from the
 * irradiance target, uploading). The same sums as the shaders, equal to float rounding
 * (tests/render/test_render_blur_cpu.c). */
#include <stdlib.h>

#include "core/dm_level_blur.h"
#include "core/dm_level_sum.h"
#include "render/input/dm_render_estimate.h"
#include "render/passes/dm_pass_blur_cpu.h"

static int stretch_index(const dmr_frame *f, int k)
{
    return k - 1 < f->stretch_count - 1 ? k - 1 : f->stretch_count - 1;
}

/* Its buffers and each pass's stretch per texel; false when out of memory. */
static bool allocate(dmr_frame *f, dmr_blur_cpu *b, const dm_render_assets *a)
{
    /* three buffers in turn: level k−1, the U pass's result, level k */
    size_t floats = dm_level_blur_floats(f->irr_edge, f->irr_edge);
    for (int i = 0; i < 3; ++i)
        if (!(b->buf[i] = malloc(sizeof(float) * floats))) return false;
    /* each pass's stretch at its texels, sampled once: the stretch never changes */
    float *st = NULL;
    for (int k = 1; k < f->plan.blur_levels; ++k) {
        const dm_texture *t = &a->stretch[stretch_index(f, k)];
        size_t n = (size_t)t->width * (size_t)t->height;
        float *grow = realloc(st, sizeof *st * 2 * n);
        if (!grow) break;
        st = grow;
        for (size_t i = 0; i < 2 * n; ++i) st[i] = dmr_stretch_value(t, i);
        int w = f->level_edge[k], h = f->level_edge[k - 1];
        b->step[k][0] = malloc(sizeof(float) * (size_t)w * (size_t)h);
        b->step[k][1] = malloc(sizeof(float) * (size_t)w * (size_t)w);
        if (!b->step[k][0] || !b->step[k][1]) break;
        dm_level_blur_step(st, t->width, t->height, w, h, false, b->step[k][0]);
        dm_level_blur_step(st, t->width, t->height, w, w, true, b->step[k][1]);
    }
    free(st);
    for (int k = 1; k < f->plan.blur_levels; ++k)
        if (!b->step[k][0] || !b->step[k][1]) return false;
    /* the diffusion pass's sum */
    if (f->diffusion_sum && !(b->sum = malloc(sizeof(float) * 4 * (size_t)f->irr_edge * (size_t)f->irr_edge)))
        return false;
    /* the thin-part map's candidates, compact (diffusion.glsl's DM_THIN: the same terms) */
    if (b->sum && f->tex_thin &&
        !dm_level_sum_thin_make(dm_render_assets_thin_map(a, f->irr_edge)->texels, f->irr_edge, &b->thin))
        return false;
    /* the thin gather, where the thin-part map is used and it was baked at this size */
    const dm_texture *gt, *gi = dm_render_assets_gather(a, f->irr_edge, &gt);
    if (b->sum && f->tex_thin && gi && f->gather_ok)
        (void)dm_level_sum_gather_make(gi->texels, f->irr_edge, gt->texels, (int64_t)gt->width * gt->height,
                                       f->plan.blur_levels, &b->gather); /* false: not used (its header does not fit) */
    return true;
}

/* Adds level k (at b->level) to the diffusion pass's sum when this frame's plan sums them. */
static void add_to_sum(const dmr_frame *f, dmr_blur_cpu *b, int k)
{
    if (!b->sum || b->sum_level != k - 1) return;
    int n = f->irr_edge; /* every level at this size (diffusion_sum) */
    dm_level_sum_add(&(dm_level_sum_pass){b->sum, b->level, dm_level_blur_stride(n), n,
                                          {f->level_weight[k][0], f->level_weight[k][1], f->level_weight[k][2]},
                                          k == 0, k == f->plan.blur_levels - 1, 0, b->thin.first ? &b->thin : NULL,
                                          (float)f->profile.variance_mm2[k], b->gather.value ? &b->gather : NULL, k});
    b->sum_level = k;
}

/* The levels' textures brought up to the chain's state: the chain again from the irradiance
 * target (which a frame reusing texture space keeps), every level uploaded. */
static void sync(dmr_frame *f, void *st)
{
    dmr_blur_cpu *b = st;
    b->syncing = true;
    for (int k = 1; k < f->profile.count; ++k) {
        dmr_blur_cpu_run(f, b, &(dm_pass){.kind = DM_PASS_BLUR_U, .index = k}, NULL);
        dmr_blur_cpu_run(f, b, &(dm_pass){.kind = DM_PASS_BLUR_V, .index = k}, NULL);
    }
    b->syncing = false;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

bool dmr_blur_cpu_sum_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    (void)ps, (void)out;
    const dmr_blur_cpu *b = st;
    return f->blur_cpu && b->sum && b->sum_level == f->plan.blur_levels - 1;
}

void dmr_blur_cpu_sum_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps, (void)opt;
    dmr_blur_cpu *b = st;
    glBindTexture(GL_TEXTURE_2D, f->diff_tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, f->irr_edge, f->irr_edge, GL_RGBA, GL_FLOAT, b->sum);
    b->sum_level = -1;
}

dm_result dmr_blur_cpu_setup(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err)
{
    dmr_blur_cpu *b = st;
    dm_blur_path path = f->desc.blur_path;
    if (path < DM_BLUR_PATH_AUTO || path > DM_BLUR_PATH_CPU)
        return dm_fail(err, DM_ERR_RANGE, "renderer: blur_path %d, expected auto (0), gl (1) or cpu (2)", (int)path);
    if (path == DM_BLUR_PATH_CPU && f->level_format != GL_RGBA32F)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT,
                       "renderer: the blur on the CPU keeps float levels: it does not take blur_half_float");
    f->blur_cpu = f->plan.texture_space && f->level_format == GL_RGBA32F && dmr_blur_cpu_wanted(&f->desc, f->software_gl);
    if (!f->blur_cpu) return DM_OK;
    if (allocate(f, b, a)) {
        b->held = b->tmp_level = b->sum_level = -1;
        f->levels = (dmr_levels_sync){0, sync, b};
        return DM_OK;
    }
    /* out of memory (three level-sized buffers, two stretch floats a texel a level, the sum): auto
     * keeps the blur in GL, cpu says so */
    size_t mb = (dm_level_blur_floats(f->irr_edge, f->irr_edge) * 4 * 3 +
                 (size_t)f->irr_edge * (size_t)f->irr_edge * (8 * (size_t)(f->plan.blur_levels - 1) + 16)) >> 20;
    dmr_blur_cpu_free(f, b);
    f->blur_cpu = false;
    if (path == DM_BLUR_PATH_AUTO) return DM_OK;
    return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "renderer: the blur on the CPU needs %zu MB more", mb);
}

void dmr_blur_cpu_free(dmr_frame *f, void *st)
{
    (void)f;
    dmr_blur_cpu *b = st;
    for (int i = 0; i < 3; ++i) free(b->buf[i]), b->buf[i] = NULL;
    free(b->sum), b->sum = NULL;
    dm_level_sum_thin_free(&b->thin);
    dm_level_sum_gather_free(&b->gather);
    for (int k = 0; k < DM_PROFILE_MAX_GAUSSIANS; ++k)
        free(b->step[k][0]), free(b->step[k][1]), b->step[k][0] = b->step[k][1] = NULL;
}

bool dmr_blur_cpu_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    (void)st, (void)ps, (void)out;
    return f->blur_cpu;
}

/* U: level k−1 into buf[0] (the V pass before left it there; level 0, the irradiance pass's,
 * is read back every time), the U result into buf[1] (n × h). */
static void blur_u(dmr_frame *f, dmr_blur_cpu *b, int k, int n, int h)
{
    if (k == 1 || b->held != k - 1) {
        b->level = dm_level_blur_frame(b->buf[0], h, h);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, f->level_fbo[k - 1]);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glPixelStorei(GL_PACK_ROW_LENGTH, (GLint)(dm_level_blur_stride(h) / 4));
        glReadPixels(0, 0, h, h, GL_RGBA, GL_FLOAT, b->level);
        glPixelStorei(GL_PACK_ROW_LENGTH, 0);
        b->held = k - 1;
    }
    if (k == 1) {
        b->summing = b->sum && dm_render_plan_find(&f->plan, "diffusion") >= 0 && !b->syncing;
        b->sum_level = b->summing ? -1 : -2;
        add_to_sum(f, b, 0);
    }
    b->tmp = dm_level_blur_frame(b->buf[1], n, h);
    dm_level_blur(&(dm_level_blur_pass){b->level, h, h, b->tmp, n, h, false, b->step[k][0], f->kernel.offset_mm[k],
                                        f->kernel.weight, f->taps, 0, dmr_frame_blur_checks(f, k) ? f->seam_points : NULL,
                                        f->seam_cuts});
    b->tmp_level = k;
}

void dmr_blur_cpu_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)opt;
    dmr_blur_cpu *b = st;
    int k = ps->index;
    int n = f->level_edge[k], h = f->level_edge[k - 1];
    if (ps->kind == DM_PASS_BLUR_U) {
        blur_u(f, b, k, n, h);
        return;
    }
    if (b->tmp_level != k) return; /* V without its U: not in any plan */
    float *level = dm_level_blur_frame(b->buf[2], n, n);
    dm_level_blur(&(dm_level_blur_pass){b->tmp, n, h, level, n, n, true, b->step[k][1], f->kernel.offset_mm[k],
                                        f->kernel.weight, f->taps, 0, dmr_frame_blur_checks(f, k) ? f->seam_points : NULL,
                                        f->seam_cuts});
    if (b->summing) {
        f->levels.stale |= 1u << k;
    } else {
        glBindTexture(GL_TEXTURE_2D, f->level_tex[k]);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, (GLint)(dm_level_blur_stride(n) / 4));
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, n, n, GL_RGBA, GL_FLOAT, level);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
        f->levels.stale &= ~(1u << k);
    }
    /* level k is the next U pass's input: its buffer becomes buf[0] */
    float *t = b->buf[0];
    b->buf[0] = b->buf[2], b->buf[2] = t;
    b->level = level, b->held = k, b->tmp_level = 0;
    add_to_sum(f, b, k);
}
