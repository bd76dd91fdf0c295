/* dm_render_estimate.c — the renderer's memory estimate (its formula: dm_render_memory.h), the
 * sizes create resolves from the assets and options, and the predicates create and the
 * estimate share. No GL: the checks against this OpenGL's limits are dm_render_limits.c. */
#include <stdio.h>
#include <string.h>

#include "core/dm_level_blur.h"
#include "core/dm_level_sum.h"
#include "core/dm_memory.h"
#include "render/dm_render_pack.h"
#include "render/input/dm_render_estimate.h"
#include "render/input/dm_render_kernel.h"

void dmr_resolve_sizes(const dm_render_assets *a, const dm_render_desc *d, dmr_sizes *s)
{
    s->width = d->width > 0 ? d->width : a->scene->width;
    s->height = d->height > 0 ? d->height : a->scene->height;
    s->irr_edge = d->irradiance_size > 0 ? d->irradiance_size : a->scene->irradiance_size;
    s->shadow_edge = d->shadow_size > 0 ? d->shadow_size : DM_RENDER_SHADOW_SIZE_DEFAULT;
    int shift = d->blur_reduce_shift > 0 ? d->blur_reduce_shift : 1;
    for (int k = 0; k < DM_PROFILE_MAX_GAUSSIANS; ++k) {
        bool reduced = d->blur_reduce_from > 0 && k >= d->blur_reduce_from;
        s->level_edge[k] = reduced ? s->irr_edge >> shift : s->irr_edge;
    }
}

bool dmr_diffusion_summed(const dm_render_plan *p, const dm_render_desc *d)
{
    return p->texture_space && !d->diffusion_per_pixel && d->blur_reduce_from == 0 && !d->blur_auto_resolution;
}

bool dmr_blur_cpu_wanted(const dm_render_desc *d, bool software_gl)
{
    return d->blur_path == DM_BLUR_PATH_CPU || (d->blur_path == DM_BLUR_PATH_AUTO && software_gl);
}

bool dmr_gather_wanted(const dm_render_assets *a, int n, bool diffusion_sum)
{
    const dm_texture *gt, *gi = dm_render_assets_gather(a, n, &gt);
    const float *h = gt ? gt->texels : NULL;
    return diffusion_sum && dm_render_assets_thin_map(a, n) && gi && h && (int64_t)gt->width * gt->height >= 2 &&
           h[2] == (float)DM_LEVEL_SUM_GATHER_FORMAT;
}

static uint64_t texels(int w, int h)
{
    return (uint64_t)(w > 0 ? w : 0) * (uint64_t)(h > 0 ? h : 0);
}

static uint64_t tex_size(const dm_texture *t)
{
    const dm_tex_format_info *f = t->texels ? dm_tex_format_get(t->format) : NULL;
    return f ? texels(t->width, t->height) * (uint64_t)(f->components * f->component_size) : 0;
}

/* A texture the plan uploads: read once from the input (inputs), copied by GL (uploads; the
 * mip chain adds a third). */
static void count_upload(dm_render_memory *m, const dm_texture *t, bool mipmaps)
{
    uint64_t n = tex_size(t);
    m->inputs_size += n;
    m->uploads_size += mipmaps ? n + n / 3 : n;
}

void dmr_memory_count(const dmr_memory_in *in, dm_render_memory *m)
{
    const dm_render_assets *a = in->a;
    const dm_render_plan *p = in->plan;
    const dmr_sizes *s = in->sizes;
    memset(m, 0, sizeof *m);
    m->gl_host_memory = in->software_gl;

    /* inputs and their GL copies (the frame's uploads and the passes' upload hooks) */
    uint64_t mesh = (uint64_t)(a->vertex_count > 0 ? a->vertex_count : 0) * DM_VERTEX_STRIDE +
                    (uint64_t)(a->index_count > 0 ? a->index_count : 0) * 4;
    m->inputs_size += mesh;
    m->uploads_size += mesh;
    count_upload(m, &a->albedo, true);
    count_upload(m, &a->normal_map, true);
    count_upload(m, &a->specular_map, true);
    count_upload(m, &a->roughness_map, true);
    if (p->effects[DM_EFFECT_SPECULAR]) count_upload(m, &a->beckmann, false);
    if (p->energy_conservation_active) count_upload(m, &a->rho_dt, false);
    if (p->env_specular_active) {
        count_upload(m, &a->env_brdf, false);
        for (int k = 0; k < a->env_level_count && k < DM_RENDER_ENV_LEVELS_MAX; ++k) {
            count_upload(m, &a->env_levels[k], false);
            m->uploads_size += tex_size(&a->env_levels[k]); /* the array copy */
        }
    }
    if (dm_render_plan_find(p, "background") >= 0) count_upload(m, &a->env_background, false);
    if (p->texture_space) {
        for (int k = 0; k < a->stretch_level_count && k < DM_PROFILE_MAX_GAUSSIANS; ++k)
            count_upload(m, &a->stretch[k], false);
        count_upload(m, &a->stretch_mask, false);
        /* the seam and thin-part maps, uploaded at the size they were baked for (dm_pass_tsd.c) */
        const dm_texture *seam = dm_render_assets_seam_map(a, s->irr_edge),
                         *thin = dm_render_assets_thin_map(a, s->irr_edge);
        if (seam) count_upload(m, seam, false);
        if (seam) m->uploads_size += texels(s->irr_edge, s->irr_edge) * 8; /* its cuts (RGBA16I, dm_pass_tsd.c) */
        if (in->diffusion_sum && thin) count_upload(m, thin, false);
        /* the thin gather: its index (for the debug view, and the GL path's too), and its taps
         * where the blur runs in GL (dm_pass_diffusion.c) */
        const dm_texture *gt, *gi = dm_render_assets_gather(a, s->irr_edge, &gt);
        if (gi) {
            count_upload(m, gi, false);
            if (in->diffusion_sum && thin && !in->cpu_blur) count_upload(m, gt, false);
        }
    }
    if (p->pre_integrated) {
        count_upload(m, &a->preintegrated, false);
        count_upload(m, &a->curvature, false);
    }

    /* shadow maps (passes/dm_pass_shadow.c): DEPTH_COMPONENT32F */
    m->shadow_size = (uint64_t)p->shadow_count * texels(s->shadow_edge, s->shadow_edge) * 4;

    /* texture space (passes/dm_pass_tsd.c) and its blur on the CPU (passes/dm_pass_blur_cpu.c) */
    const uint64_t N2 = texels(s->irr_edge, s->irr_edge);
    if (p->texture_space) {
        const uint64_t level = in->half_levels ? 8 : 16;
        const int *e = s->level_edge;
        for (int k = 0; k < p->blur_levels; ++k) m->texture_space_size += texels(e[k], e[k]) * level;
        for (int k = 1; k < p->blur_levels; ++k) {
            int j = 1; /* one U target per distinct size */
            while (j < k && !(e[j] == e[k] && e[j - 1] == e[k - 1])) ++j;
            if (j == k) m->texture_space_size += texels(e[k], e[k - 1]) * level;
        }
        if (in->diffusion_sum) m->texture_space_size += N2 * 16;
        m->texture_space_size += N2 * (4 * 16 + 4); /* the surface G-buffer and its depth */
        if (dm_render_assets_seam_map(a, s->irr_edge))
            m->texture_space_size += N2 * 16; /* the seam points */
    }

    /* the screen (frame/dm_frame_targets.c) */
    const uint64_t px = texels(s->width, s->height);
    uint64_t per_px = 16 + 4; /* screen RGBA32F, depth */
    if (p->deferred) per_px += 4 * 16;
    if (p->screen_space) per_px += 16 + 8 + 16 + 16;
    if (p->effects[DM_EFFECT_TONEMAP]) per_px += 4;
    const uint64_t glow_px = texels(s->width / 2 > 0 ? s->width / 2 : 1, s->height / 2 > 0 ? s->height / 2 : 1);
    m->screen_size = px * per_px;
    if (p->effects[DM_EFFECT_GLOW]) m->screen_size += glow_px * 32;
    if (!in->software_gl) { /* a GPU holds GL's textures and targets itself */
        m->uploads_size = m->shadow_size = m->texture_space_size = m->screen_size = 0;
    }
    m->driver_size = in->software_gl ? DM_RENDER_MEMORY_DRIVER_SIZE : 0;

    /* the CPU's share: blur buffers, read-back (the seam points and their cuts, read back once) */
    if (p->texture_space && dm_render_assets_seam_map(a, s->irr_edge)) m->cpu_blur_size += N2 * (16 + 8);
    if (p->texture_space && in->cpu_blur) {
        const int *e = s->level_edge;
        m->cpu_blur_size += 3 * (uint64_t)dm_level_blur_floats(s->irr_edge, s->irr_edge) * 4;
        for (int k = 1; k < p->blur_levels; ++k)
            m->cpu_blur_size += (texels(e[k], e[k - 1]) + texels(e[k], e[k])) * 4;
        if (in->diffusion_sum) m->cpu_blur_size += N2 * 16;
        const dm_texture *thin = dm_render_assets_thin_map(a, s->irr_edge);
        if (in->diffusion_sum && thin && thin->texels) { /* the candidates' compact copy (core/dm_level_sum.h) */
            const float *tx = thin->texels;
            uint64_t with = 0, cands = 0;
            for (uint64_t i = 0; i < N2; ++i) {
                int c = (tx[4 * i + 3] > 0.5f) + (tx[4 * (N2 + i) + 3] > 0.5f);
                with += c > 0, cands += (uint64_t)c;
            }
            m->cpu_blur_size += ((uint64_t)s->irr_edge + 1) * 4 + with * 8 + cands * 16;
        }
        const dm_texture *gt;
        if (in->diffusion_sum && dm_render_assets_gather(a, s->irr_edge, &gt) && gt->texels) {
            /* the sums' compact copy (core/dm_level_sum.h): 8 bytes a tap, a UV and a value (24
             * bytes) a site read (the header's site count, bake/dm_thin_gather.h, at most), a
             * gathering texel's column and run, and a run's (at most one a texel) first taps per
             * level and sum */
            const float *h = gt->texels;
            uint64_t all = texels(gt->width, gt->height), sites = all >= 2 && h[3] > 0.0f ? (uint64_t)h[3] : 0;
            sites = sites < all ? sites : all;
            uint64_t gathering = 0;
            const dm_texture *gi = dm_render_assets_gather(a, s->irr_edge, &gt);
            const float *ix = gi->texels;
            for (uint64_t i = 0; ix && i < N2; ++i) gathering += ix[4 * i + 1] > 0.0f || ix[4 * i + 2] > 0.0f;
            uint64_t levels = all >= 2 && h[1] >= 1.0f && h[1] <= 4.0f ? (uint64_t)h[1] : 4;
            m->cpu_blur_size += (all - sites) * 8 + sites * 24 + gathering * (8 + 4 * levels + 16) +
                                ((uint64_t)s->irr_edge + 1) * 4;
        }
    }
    if (p->effects[DM_EFFECT_GLOW] && in->cpu_glow) m->cpu_blur_size += glow_px * 32;
    m->readback_size = px * (16 + 4 + 4);
    m->total_size = m->driver_size + m->inputs_size + m->uploads_size + m->shadow_size + m->texture_space_size +
                    m->screen_size + m->cpu_blur_size + m->readback_size;
}

dm_result dm_render_memory_estimate(const dm_render_assets *a, const dm_render_desc *desc, bool software_gl,
                                    dm_render_memory *out, dm_error *err)
{
    memset(out, 0, sizeof *out);
    dm_render_plan plan;
    dm_scene scene = *a->scene;
    scene.profile = a->profile ? *a->profile : a->scene->profile;
    dm_result rc = dm_render_plan_build(&scene, DM_VIEW_FINAL, 0, &plan, err);
    if (rc != DM_OK) return rc;
    dmr_sizes s;
    dmr_resolve_sizes(a, desc, &s);
    if (plan.texture_space) dmr_auto_level_edges(a, desc, &scene.profile, s.irr_edge, s.level_edge);
    bool wanted = dmr_blur_cpu_wanted(desc, software_gl);
    dmr_memory_in in = {.a = a, .plan = &plan, .sizes = &s, .desc = desc, .half_levels = desc->blur_half_float,
                        .diffusion_sum = dmr_diffusion_summed(&plan, desc), .software_gl = software_gl,
                        .cpu_blur = wanted && !desc->blur_half_float, .cpu_glow = wanted};
    dmr_memory_count(&in, out);
    return DM_OK;
}

dm_result dm_render_memory_estimate_pack(const dm_pack *pack, const dm_render_desc *desc, bool software_gl,
                                         dm_render_memory *out, dm_error *err)
{
    dm_scene scene;
    dm_profile profile;
    dm_render_assets assets;
    dm_result rc = dm_render_assets_from_pack(pack, &scene, &profile, &assets, err);
    if (rc != DM_OK) {
        memset(out, 0, sizeof *out);
        return rc;
    }
    return dm_render_memory_estimate(&assets, desc, software_gl, out, err);
}

void dm_render_memory_text(const dm_render_memory *m, char *out, size_t out_size)
{
    struct part { const char *name; uint64_t size; } part[] = {
        {"texture space", m->texture_space_size}, {"blur on the CPU", m->cpu_blur_size},
        {"screen targets", m->screen_size},       {"read-back", m->readback_size},
        {"shadow maps", m->shadow_size},          {"uploads", m->uploads_size},
        {"inputs", m->inputs_size},               {"OpenGL driver", m->driver_size}};
    enum { PARTS = sizeof part / sizeof part[0] };
    for (int i = 1; i < PARTS; ++i) /* largest first */
        for (int j = i; j > 0 && part[j].size > part[j - 1].size; --j) {
            struct part t = part[j];
            part[j] = part[j - 1], part[j - 1] = t;
        }
    size_t n = 0;
    out[0] = 0;
    for (int i = 0; i < PARTS && n < out_size && part[i].size; ++i) {
        char t[32];
        dm_memory_size_text(part[i].size, t, sizeof t);
        n += (size_t)snprintf(out + n, out_size - n, "%s%s %s", i ? ", " : "", part[i].name, t);
    }
}
