/* dm_render_limits.c — what this OpenGL makes (dm_render_memory.h's limits and proxy
 * queries), and the checks dm_renderer_create makes before its first texture: each target
 * the plan makes within those limits, then the memory estimate within the memory available. */
#include <stdio.h>
#include <string.h>

#include "core/dm_memory.h"
#include "render/dm_render_internal.h"
#include "render/input/dm_render_estimate.h"

void dm_render_gl_limits_get(dm_render_gl_limits *out)
{
    GLint v = 0, vp[2] = {0, 0};
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &v);
    out->max_texture_size = v;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &v);
    out->max_renderbuffer_size = v;
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, vp);
    out->max_viewport[0] = vp[0], out->max_viewport[1] = vp[1];
}

bool dm_render_gl_can_make(unsigned int internal, int width, int height)
{
    bool depth = internal == GL_DEPTH_COMPONENT32F || internal == GL_DEPTH_COMPONENT24;
    GLint w = 0;
    glTexImage2D(GL_PROXY_TEXTURE_2D, 0, (GLint)internal, width, height, 0, depth ? GL_DEPTH_COMPONENT : GL_RGBA,
                 GL_FLOAT, NULL);
    glGetTexLevelParameteriv(GL_PROXY_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &w);
    glGetError(); /* a proxy beyond GL_MAX_TEXTURE_SIZE raises GL_INVALID_VALUE: that is the answer, not an error */
    return w == width;
}

int dm_render_gl_largest_square(unsigned int internal, int max_edge)
{
    int lo = 0, hi = max_edge; /* lo makes one (0: none yet), hi + 1 does not */
    while (lo < hi) {
        int mid = lo + (hi - lo + 1) / 2;
        if (dm_render_gl_can_make(internal, mid, mid)) lo = mid;
        else hi = mid - 1;
    }
    return lo;
}

static const char *format_name(GLenum f)
{
    return f == GL_RGBA32F ? "RGBA32F" : f == GL_RGBA16F ? "RGBA16F" : f == GL_DEPTH_COMPONENT32F ? "32-bit depth" : "RGBA8";
}

/* One target the plan makes: within the context's limits, or a refusal that names them. */
static dm_result check_target(const dm_renderer *r, const dm_render_gl_limits *L, const char *what, const char *target,
                              GLenum format, int w, int h, bool renderbuffer, dm_error *err)
{
    int max_w = L->max_texture_size, max_h = L->max_texture_size;
    if (renderbuffer) {
        if (L->max_renderbuffer_size < max_w) max_w = max_h = L->max_renderbuffer_size;
        if (L->max_viewport[0] < max_w) max_w = L->max_viewport[0];
        if (L->max_viewport[1] < max_h) max_h = L->max_viewport[1];
    }
    if (w > max_w || h > max_h)
        return dm_fail(err, DM_ERR_RANGE,
                       "renderer: %s %dx%d: beyond this OpenGL's limits (%s: GL_MAX_TEXTURE_SIZE %d, "
                       "GL_MAX_RENDERBUFFER_SIZE %d, GL_MAX_VIEWPORT_DIMS %dx%d): at most %dx%d",
                       what, w, h, r->gl_name, L->max_texture_size, L->max_renderbuffer_size, L->max_viewport[0],
                       L->max_viewport[1], max_w, max_h);
    if (dm_render_gl_can_make(format, w, h)) return DM_OK;
    const int bpt = format == GL_RGBA32F ? 16 : format == GL_RGBA16F ? 8 : 4;
    char size[32];
    dm_memory_size_text((uint64_t)w * (uint64_t)h * (uint64_t)bpt, size, sizeof size);
    int sq = dm_render_gl_largest_square(format, w > h ? w : h);
    return dm_fail(err, DM_ERR_RANGE,
                   "renderer: %s %dx%d: this OpenGL (%s) does not make its %s target, %dx%d %s (%s in one texture: "
                   "more than it holds in one, although within GL_MAX_TEXTURE_SIZE %d); the largest square it makes "
                   "in that format is %dx%d",
                   what, w, h, r->gl_name, target, w, h, format_name(format), size, L->max_texture_size, sq, sq);
}

dm_result dmr_check_limits(const dm_renderer *r, const dm_render_assets *a, dm_error *err)
{
    const dm_render_plan *p = &r->f.plan;
    dm_render_gl_limits L;
    dm_render_gl_limits_get(&L);
    glGetError();
    dm_result rc = check_target(r, &L, "output size", "screen", GL_RGBA32F, r->f.width, r->f.height, true, err);
    if (rc == DM_OK && p->texture_space) {
        rc = check_target(r, &L, "irradiance size", "surface G-buffer", GL_RGBA32F, r->f.irr_edge, r->f.irr_edge, true, err);
        if (rc == DM_OK && r->f.level_format != GL_RGBA32F)
            rc = check_target(r, &L, "irradiance size", "irradiance", r->f.level_format, r->f.irr_edge, r->f.irr_edge, true,
                              err);
    }
    if (rc == DM_OK && p->shadow_count)
        rc = check_target(r, &L, "shadow map size", "shadow", GL_DEPTH_COMPONENT32F, r->f.shadow_edge, r->f.shadow_edge,
                          true, err);
    if (rc != DM_OK || r->f.desc.memory_available_size == UINT64_MAX) return rc;

    /* memory: the estimate as create resolved it, against what is available */
    dmr_sizes s = {r->f.width, r->f.height, r->f.irr_edge, r->f.shadow_edge, {0}};
    memcpy(s.level_edge, r->f.level_edge, sizeof s.level_edge);
    bool wanted = dmr_blur_cpu_wanted(&r->f.desc, r->f.software_gl);
    dmr_memory_in in = {.a = a, .plan = p, .sizes = &s, .desc = &r->f.desc, .half_levels = r->f.level_format != GL_RGBA32F,
                        .diffusion_sum = r->f.diffusion_sum, .software_gl = r->f.software_gl,
                        .cpu_blur = wanted && r->f.level_format == GL_RGBA32F, .cpu_glow = wanted};
    dm_render_memory m;
    dmr_memory_count(&in, &m);
    dm_memory_available avail;
    if (r->f.desc.memory_available_size) {
        avail.size = r->f.desc.memory_available_size;
        snprintf(avail.source, sizeof avail.source, "dm_render_desc.memory_available_size");
    } else {
        dm_memory_available_get(&avail);
    }
    char what[128], parts[512];
    if (p->texture_space) snprintf(what, sizeof what, "the renderer at %dx%d, irradiance %d", r->f.width, r->f.height, r->f.irr_edge);
    else snprintf(what, sizeof what, "the renderer at %dx%d", r->f.width, r->f.height);
    dm_render_memory_text(&m, parts, sizeof parts);
    const char *advice = p->texture_space ? "lower the irradiance size (--irradiance) or the output size (--size)"
                                          : "lower the output size (--size)";
    return dm_memory_check_against(m.total_size, &avail, what, parts, advice, err);
}
