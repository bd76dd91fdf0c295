/* dm_pass_view.c — texture debug views (irradiance, blurK, stretchK, shadowK, diffusion,
 * curvature, seam, thin): the texels at their own size into the frame's "view" target, then
 * stretched over the screen; the stretch and curvature maps, and the seam and thin-part maps'
 * distances, through a colour scale whose range (dm_renderer_view_scale) a legend names. The
 * pass binds its two targets itself. */
#include <math.h>
#include <stdlib.h>

#include "core/dm_sort.h"
#include "render/passes/dm_pass_view.h"

/* The texture a texture view shows and its size in texels. */
static GLuint view_source(const dmr_frame *f, int *w, int *h, int *cov_shift)
{
    const dm_render_plan *pl = &f->plan;
    int k = pl->view_index;
    GLuint tex;
    *cov_shift = 0;
    if (pl->view == DM_VIEW_SHADOW) {
        *w = *h = f->shadow_edge;
        return f->shadow_tex[k];
    }
    if (pl->view == DM_VIEW_SEAM || pl->view == DM_VIEW_THIN || pl->view == DM_VIEW_GATHER) {
        /* at the irradiance grid (thin: layer 0's rows) */
        *w = *h = f->irr_edge;
        tex = pl->view == DM_VIEW_SEAM ? f->tex_seam : pl->view == DM_VIEW_THIN ? f->tex_thin : f->tex_gather_view;
        return tex ? tex : f->tex_black;
    }
    if (pl->view == DM_VIEW_STRETCH || pl->view == DM_VIEW_CURVATURE) {
        tex = pl->view == DM_VIEW_CURVATURE ? f->preint.curvature : f->tex_stretch[k < f->stretch_count ? k : f->stretch_count - 1];
        glBindTexture(GL_TEXTURE_2D, tex);
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, w);
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, h);
        return tex;
    }
    int level = pl->view == DM_VIEW_BLUR ? k : 0; /* irradiance, diffusion: level 0's size */
    *w = *h = f->level_edge[level];
    while ((f->level_edge[level] << *cov_shift) < f->irr_edge) ++*cov_shift;
    return f->level_tex[level];
}

/* The colour scale of a stretch or curvature view: the 1st and 99th percentiles of its
 * scalar (mm per texel, or 1/mm) over the charts, from the source texture (w x h). */
static void scalar_range(dmr_view *v, const dmr_frame *f, GLuint src, int w, int h, bool stretch)
{
    size_t n = (size_t)w * h, k = 0;
    float *t = malloc(n * 2 * sizeof *t), *m = stretch && f->tex_mask ? malloc(n * sizeof *m) : NULL, *val = malloc(n * sizeof *val);
    int mw = 0, mh = 0;
    if (m) {
        glBindTexture(GL_TEXTURE_2D, f->tex_mask);
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &mw);
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, &mh);
        if (mw == w && mh == h) glGetTexImage(GL_TEXTURE_2D, 0, GL_RED, GL_FLOAT, m);
        else free(m), m = NULL;
    }
    v->lo = 0.0f, v->hi = 1.0f;
    if (t && val) {
        glBindTexture(GL_TEXTURE_2D, src);
        glGetTexImage(GL_TEXTURE_2D, 0, stretch ? GL_RG : GL_RED, GL_FLOAT, t);
        for (size_t i = 0; i < n; ++i) {
            double s = stretch ? (t[2 * i] * t[2 * i + 1] > 0 ? 1.0 / (w * sqrt((double)t[2 * i] * t[2 * i + 1])) : NAN)
                               : t[i];
            if (isfinite(s) && (!m || m[i] >= 0.5f)) val[k++] = (float)s;
        }
        if (k) {
            dm_sort_floats(val, k);
            v->lo = val[k / 100], v->hi = val[k - 1 - k / 100];
            if (!(v->hi > v->lo)) v->hi = v->lo + 1e-6f;
        }
    }
    free(t), free(m), free(val);
}

/* Before anything is bound: a blur level whose upload a chain deferred (a frame reusing
 * texture space) brought up, the source found, the view target sized to it. */
bool dmr_view_prepare(dmr_frame *f, void *st, const dm_pass *ps, dmr_output *out)
{
    (void)ps, (void)out;
    dmr_view *v = st;
    if (f->plan.view == DM_VIEW_BLUR) dmr_levels_need(f, 1u << f->plan.view_index);
    v->width = v->height = 1, v->cov_shift = 0;
    v->src = view_source(f, &v->width, &v->height, &v->cov_shift);
    dmg_target *vt = &f->gpu.targets[f->view_target];
    if (vt->width != v->width || vt->height != v->height) { /* the same texture, its storage made anew */
        glBindTexture(GL_TEXTURE_2D, f->view_tex);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, v->width, v->height, 0, GL_RGBA, GL_FLOAT, NULL);
        vt->width = v->width, vt->height = v->height;
    }
    return true;
}

/* Texture views: the texels at their own size into "view" (RGBA32F, full precision, alpha =
 * coverage), then that target stretched over the screen for display. */
void dmr_view_run(dmr_frame *f, void *st, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps;
    dmr_view *v = st;
    GLuint p = f->prog[DM_PASS_VIEW];
    const dm_render_plan *pl = &f->plan;
    int w = v->width, h = v->height, shift = v->cov_shift;
    GLuint src = v->src;
    dmg_target_begin(f->view_fbo, w, h);
    glUseProgram(p);
    dmg_u1f(p, "u_scale", opt->view_scale > 0 ? opt->view_scale : 1.0f);
    dmg_u2f(p, "u_size", (float)w, (float)h);
    dmg_u1i(p, "u_cov_shift", shift);
    if (pl->view == DM_VIEW_SHADOW) {
        dmg_u1i(p, "u_mode", 2);
        dmg_bind(UNIT_DEPTH, GL_TEXTURE_2D, src);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_NONE);
        dmr_draw_fullscreen(f);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    } else {
        bool stretch = pl->view == DM_VIEW_STRETCH,
             map = pl->view == DM_VIEW_SEAM || pl->view == DM_VIEW_THIN || pl->view == DM_VIEW_GATHER;
        dmg_u1i(p, "u_mode", map ? 7 : stretch ? 1 : pl->view == DM_VIEW_CURVATURE ? 5 : pl->view == DM_VIEW_DIFFUSION ? 3 : 0);
        dmg_u1i(p, "u_map_kind", pl->view == DM_VIEW_THIN ? 1 : pl->view == DM_VIEW_GATHER ? 2 : 0);
        dmg_bind(UNIT_SRC, GL_TEXTURE_2D, src);
        dmg_bind(UNIT_COVER, GL_TEXTURE_2D, f->ts_cover_tex ? f->ts_cover_tex : f->tex_black);
        if (stretch) {
            dmg_bind(UNIT_MASK, GL_TEXTURE_2D, f->tex_mask ? f->tex_mask : f->tex_black);
            dmg_u1i(p, "u_has_mask", f->tex_mask != 0);
        }
        dmr_draw_fullscreen(f);
    }
    /* display copy; stretch and curvature through the colour scale (range cached per map); the
     * seam and thin maps through it from 0 to the reach (3 sigma of the widest Gaussian), the
     * thin gather from 0 to the most taps a texel has */
    bool map = pl->view == DM_VIEW_SEAM || pl->view == DM_VIEW_THIN || pl->view == DM_VIEW_GATHER;
    bool scalar = pl->view == DM_VIEW_STRETCH || pl->view == DM_VIEW_CURVATURE || map;
    if (pl->view == DM_VIEW_GATHER) {
        v->lo = 0.0f, v->hi = f->gather_view_max > 0 ? f->gather_view_max : 1.0f;
        v->range_of = 0;
    } else if (map) {
        v->lo = 0.0f, v->hi = (float)(3.0 * sqrt(f->profile.variance_mm2[f->profile.count - 1]));
        v->range_of = 0;
    } else if (scalar && v->range_of != src) {
        scalar_range(v, f, src, w, h, pl->view == DM_VIEW_STRETCH);
        v->range_of = src;
    }
    dmg_target_begin(f->screen_fbo, f->width, f->height);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    /* the texture at its own aspect, centred (a 16:9 window shows a square map square) */
    double fit = fmin((double)f->width / w, (double)f->height / h);
    int vw = (int)lround(w * fit), vh = (int)lround(h * fit);
    glViewport((f->width - vw) / 2, (f->height - vh) / 2, vw > 0 ? vw : 1, vh > 0 ? vh : 1);
    glUseProgram(p);
    dmg_u1i(p, "u_mode", scalar ? 6 : 4);
    dmg_u1i(p, "u_flagged", map);
    dmg_bind(UNIT_SRC, GL_TEXTURE_2D, scalar && !map ? src : f->view_tex);
    if (scalar) {
        dmg_u1f(p, "u_lo", v->lo);
        dmg_u1f(p, "u_hi", v->hi);
        dmg_u1i(p, "u_stretch", pl->view == DM_VIEW_STRETCH);
        dmg_bind(UNIT_MASK, GL_TEXTURE_2D, f->tex_mask ? f->tex_mask : f->tex_black);
        dmg_u1i(p, "u_has_mask", pl->view == DM_VIEW_STRETCH && f->tex_mask != 0);
    }
    dmr_draw_fullscreen(f);
    f->view_in_target = true;
}
