/* dm_render_view.c — texture debug views (irradiance, blurK, stretchK, shadowK, diffusion,
 * curvature): the texels at their own size into the "view" target, then stretched over the
 * screen; the stretch and curvature maps through a colour scale whose range
 * (dm_renderer_view_scale) a legend names. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/dm_render_internal.h"
#include "render/dm_render_legend.h"
#include "core/dm_sort.h"

/* The texture a texture view shows and its size in texels. */
static GLuint view_source(const dm_renderer *r, int *w, int *h, int *cov_shift)
{
    const dm_render_plan *pl = &r->plan;
    int k = pl->view_index;
    GLuint tex;
    *cov_shift = 0;
    if (pl->view == DM_VIEW_SHADOW) {
        *w = *h = r->shadow_edge;
        return r->shadow_tex[k];
    }
    if (pl->view == DM_VIEW_STRETCH || pl->view == DM_VIEW_CURVATURE) {
        tex = pl->view == DM_VIEW_CURVATURE ? r->tex_curvature : r->tex_stretch[k < r->stretch_count ? k : r->stretch_count - 1];
        glBindTexture(GL_TEXTURE_2D, tex);
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, w);
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, h);
        return tex;
    }
    int level = pl->view == DM_VIEW_BLUR ? k : 0; /* irradiance, diffusion: level 0's size */
    *w = *h = r->level_edge[level];
    while ((r->level_edge[level] << *cov_shift) < r->irr_edge) ++*cov_shift;
    return r->irr_tex[level];
}

/* The colour scale of a stretch or curvature view: the 1st and 99th percentiles of its
 * scalar (mm per texel, or 1/mm) over the charts, from the source texture (w x h). */
static void scalar_range(dm_renderer *r, GLuint src, int w, int h, bool stretch)
{
    size_t n = (size_t)w * h, k = 0;
    float *t = malloc(n * 2 * sizeof *t), *m = stretch && r->tex_mask ? malloc(n * sizeof *m) : NULL, *v = malloc(n * sizeof *v);
    int mw = 0, mh = 0;
    if (m) {
        glBindTexture(GL_TEXTURE_2D, r->tex_mask);
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &mw);
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, &mh);
        if (mw == w && mh == h) glGetTexImage(GL_TEXTURE_2D, 0, GL_RED, GL_FLOAT, m);
        else free(m), m = NULL;
    }
    r->view_lo = 0.0f, r->view_hi = 1.0f;
    if (t && v) {
        glBindTexture(GL_TEXTURE_2D, src);
        glGetTexImage(GL_TEXTURE_2D, 0, stretch ? GL_RG : GL_RED, GL_FLOAT, t);
        for (size_t i = 0; i < n; ++i) {
            double s = stretch ? (t[2 * i] * t[2 * i + 1] > 0 ? 1.0 / (w * sqrt((double)t[2 * i] * t[2 * i + 1])) : NAN)
                               : t[i];
            if (isfinite(s) && (!m || m[i] >= 0.5f)) v[k++] = (float)s;
        }
        if (k) {
            dm_sort_floats(v, k);
            r->view_lo = v[k / 100], r->view_hi = v[k - 1 - k / 100];
            if (!(r->view_hi > r->view_lo)) r->view_hi = r->view_lo + 1e-6f;
        }
    }
    free(t), free(m), free(v);
}

void dm_renderer_view_scale(const dm_renderer *r, float *lo, float *hi, const char **quantity)
{
    bool scaled = r->plan.view == DM_VIEW_STRETCH || r->plan.view == DM_VIEW_CURVATURE;
    *lo = scaled ? r->view_lo : 0.0f, *hi = scaled ? r->view_hi : 0.0f;
    if (quantity)
        *quantity = r->plan.view == DM_VIEW_STRETCH ? "mm per texel"
                    : r->plan.view == DM_VIEW_CURVATURE ? "mean curvature, 1/mm"
                                                        : NULL;
}

float dm_renderer_view_gain(const dm_renderer *r)
{
    return r->plan.view == DM_VIEW_SPECULAR && r->view_gain > 0 ? r->view_gain : 1.0f;
}

/* A stretch or curvature view's PNG: its colour scale's legend in a strip below the picture
 * (*px, RGBA8, grows by the strip; *h with it). Other views unchanged. */
dm_result dm_render_view_with_legend(const dm_renderer *r, void **px, int w, int *h, dm_error *err)
{
    float lo, hi;
    const char *quantity;
    dm_renderer_view_scale(r, &lo, &hi, &quantity);
    if (!quantity) return DM_OK;
    int lh = dm_render_scalar_legend_height(w), nh = *h + lh;
    uint8_t *out = malloc((size_t)w * nh * 4);
    if (!out) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "cannot allocate the legend");
    memset(out, 0, (size_t)w * lh * 4);
    memcpy(out + (size_t)w * lh * 4, *px, (size_t)w * *h * 4); /* bottom-up: the strip is the first rows */
    dm_render_scalar_legend(out, w, nh, lo, hi, quantity);
    free(*px);
    *px = out, *h = nh;
    return DM_OK;
}

/* Texture views: the texels at their own size into "view" (RGBA32F, full precision, alpha =
 * coverage), then that target stretched over the screen for display. */
void dmr_pass_view(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps;
    GLuint p = r->prog[DM_PASS_VIEW];
    const dm_render_plan *pl = &r->plan;
    int w = 1, h = 1, shift = 0;
    if (pl->view == DM_VIEW_BLUR && (r->levels_stale >> pl->view_index & 1u))
        dmr_blur_cpu_sync(r); /* a frame reusing texture space made by a chain that did not upload */
    GLuint src = view_source(r, &w, &h, &shift);
    target *vt = &r->targets[r->view_target];
    if (vt->width != w || vt->height != h) {
        glBindTexture(GL_TEXTURE_2D, r->view_tex);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, h, 0, GL_RGBA, GL_FLOAT, NULL);
        vt->width = w, vt->height = h;
    }
    dmr_target_begin(r->view_fbo, w, h);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(p);
    u1f(p, "u_scale", opt->view_scale > 0 ? opt->view_scale : 1.0f);
    u2f(p, "u_size", (float)w, (float)h);
    u1i(p, "u_cov_shift", shift);
    dmr_bind_levels(r, p);
    if (pl->view == DM_VIEW_SHADOW) {
        u1i(p, "u_mode", 2);
        dmr_bind(UNIT_DEPTH, GL_TEXTURE_2D, src);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_NONE);
        dmr_draw_fullscreen(r);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    } else {
        bool stretch = pl->view == DM_VIEW_STRETCH;
        u1i(p, "u_mode", stretch ? 1 : pl->view == DM_VIEW_CURVATURE ? 5 : pl->view == DM_VIEW_DIFFUSION ? 3 : 0);
        dmr_bind(UNIT_SRC, GL_TEXTURE_2D, src);
        if (stretch) {
            dmr_bind(UNIT_MASK, GL_TEXTURE_2D, r->tex_mask ? r->tex_mask : r->tex_black);
            u1i(p, "u_has_mask", r->tex_mask != 0);
        }
        dmr_draw_fullscreen(r);
    }
    /* display copy; stretch and curvature through the colour scale (range cached per map) */
    bool scalar = pl->view == DM_VIEW_STRETCH || pl->view == DM_VIEW_CURVATURE;
    if (scalar && r->view_range_of != src) {
        scalar_range(r, src, w, h, pl->view == DM_VIEW_STRETCH);
        r->view_range_of = src;
    }
    dmr_target_begin(r->screen_fbo, r->width, r->height);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    /* the texture at its own aspect, centred (a 16:9 window shows a square map square) */
    double fit = fmin((double)r->width / w, (double)r->height / h);
    int vw = (int)lround(w * fit), vh = (int)lround(h * fit);
    glViewport((r->width - vw) / 2, (r->height - vh) / 2, vw > 0 ? vw : 1, vh > 0 ? vh : 1);
    glUseProgram(p);
    u1i(p, "u_mode", scalar ? 6 : 4);
    dmr_bind(UNIT_SRC, GL_TEXTURE_2D, scalar ? src : r->view_tex);
    if (scalar) {
        u1f(p, "u_lo", r->view_lo);
        u1f(p, "u_hi", r->view_hi);
        u1i(p, "u_stretch", pl->view == DM_VIEW_STRETCH);
        dmr_bind(UNIT_MASK, GL_TEXTURE_2D, r->tex_mask ? r->tex_mask : r->tex_black);
        u1i(p, "u_has_mask", pl->view == DM_VIEW_STRETCH && r->tex_mask != 0);
    }
    dmr_draw_fullscreen(r);
    r->view_in_target = true;
}
