/* dm_render_view.c — texture debug views (irradiance, blurK, stretchK, shadowK, diffusion): the
 * texels at their own size into the "view" target, then stretched over the screen. */
#include "render/dm_render_internal.h"

/* The texture a texture view shows and its size in texels. */
static GLuint view_source(const dm_renderer *r, int *w, int *h, int *cov_shift)
{
    const dm_render_plan *pl = &r->plan;
    int k = pl->view_index;
    GLuint tex;
    *cov_shift = 0;
    if (pl->view == DM_VIEW_SHADOW) {
        *w = *h = r->shadow_size;
        return r->shadow_tex[k];
    }
    if (pl->view == DM_VIEW_STRETCH) {
        tex = r->tex_stretch[k < r->stretch_count ? k : r->stretch_count - 1];
        glBindTexture(GL_TEXTURE_2D, tex);
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, w);
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, h);
        return tex;
    }
    int level = pl->view == DM_VIEW_BLUR ? k : 0; /* irradiance, diffusion: level 0's size */
    *w = *h = r->level_size[level];
    while ((r->level_size[level] << *cov_shift) < r->irr_size) ++*cov_shift;
    return r->irr_tex[level];
}

/* Texture views: the texels at their own size into "view" (RGBA32F, full precision, alpha =
 * coverage), then that target stretched over the screen for display. */
void dmr_pass_view(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    (void)ps;
    GLuint p = r->prog[DM_PASS_VIEW];
    const dm_render_plan *pl = &r->plan;
    int w = 1, h = 1, shift = 0;
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
        u1i(p, "u_mode", stretch ? 1 : pl->view == DM_VIEW_DIFFUSION ? 3 : 0);
        dmr_bind(UNIT_SRC, GL_TEXTURE_2D, src);
        if (stretch) {
            dmr_bind(UNIT_MASK, GL_TEXTURE_2D, r->tex_mask ? r->tex_mask : r->tex_black);
            u1i(p, "u_has_mask", r->tex_mask != 0);
        }
        dmr_draw_fullscreen(r);
    }
    /* display copy */
    dmr_target_begin(r->screen_fbo, r->width, r->height);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    u1i(p, "u_mode", 4);
    dmr_bind(UNIT_SRC, GL_TEXTURE_2D, r->view_tex);
    dmr_draw_fullscreen(r);
    r->view_in_target = true;
}
