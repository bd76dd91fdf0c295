/* dm_frame_state.c — a pass's GL state and clears applied from its row's data, and the
 * default state every pass ends in (dm_frame_pass.h); the small per-frame queries passes share. */
#include "render/frame/dm_frame_pass.h"

void dmr_state_apply(const dmr_frame *f, const dmr_gl_state *s)
{
    if (s->depth_test) {
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(s->depth_test);
    } else {
        glDisable(GL_DEPTH_TEST);
    }
    glDepthMask(s->depth_read_only ? GL_FALSE : GL_TRUE);
    if (s->cull_back) {
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);
    } else {
        glDisable(GL_CULL_FACE);
    }
    glPolygonMode(GL_FRONT_AND_BACK, s->wireframe ? GL_LINE : GL_FILL);
    if (s->blend_add) {
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
    } else {
        glDisable(GL_BLEND);
    }
    if (s->polygon_offset[0] != 0.0f || s->polygon_offset[1] != 0.0f) {
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(s->polygon_offset[0], s->polygon_offset[1]);
    } else {
        glDisable(GL_POLYGON_OFFSET_FILL);
    }
    GLbitfield bits = 0;
    if (s->clear & DMR_CLEAR_COLOR) bits |= GL_COLOR_BUFFER_BIT;
    if (s->clear & DMR_CLEAR_DEPTH) bits |= GL_DEPTH_BUFFER_BIT;
    if ((s->clear & DMR_CLEAR_SCREEN) && dm_render_plan_find(&f->plan, "background") < 0) bits |= GL_COLOR_BUFFER_BIT;
    if (s->clear & DMR_CLEAR_COLOR0) glClearBufferfv(GL_COLOR, 0, s->clear_color);
    if (bits) {
        glClearColor(s->clear_color[0], s->clear_color[1], s->clear_color[2], s->clear_color[3]);
        glClear(bits);
    }
}

void dmr_state_reset(void)
{
    glDisable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_BLEND);
    glDisable(GL_POLYGON_OFFSET_FILL);
}

void dmr_levels_need(dmr_frame *f, unsigned mask)
{
    if ((f->levels.stale & mask) && f->levels.sync) f->levels.sync(f, f->levels.state);
}

int dmr_view_mode(const dmr_frame *f)
{
    static const int modes[DM_VIEW_COUNT] = {[DM_VIEW_FINAL] = 0, [DM_VIEW_SPECULAR] = 1, [DM_VIEW_DIFFUSE] = 2,
                                             [DM_VIEW_UV_TEST] = 3, [DM_VIEW_WIREFRAME] = 4};
    return modes[f->plan.view];
}
