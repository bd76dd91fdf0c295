/* dm_pass_preint.c — the pre-integrated technique (Penner, "Pre-Integrated Skin Shading",
 * GPU Pro 2, 2011): no pass of its own. The final pass (final.glsl with DM_PRE_INTEGRATED)
 * looks each light's diffuse up in the baked table D(N.L, curvature) per channel
 * (bake/dm_preintegrated.h), with the curvature of the texel (bake/dm_curvature.h; concave
 * reads as flat, beyond the table's range as its last row), and a normal per channel between
 * the normal map's and the geometric one: channel c bends toward the geometric normal by
 * 1 − (its narrowest Gaussian's share of the profile), so the widely scattered red loses
 * the map's detail most (Penner's "blurred normals per channel", as a blend). Shadows multiply
 * Lambert's part of the looked-up light; the light the blur moved past the terminator is
 * shadowed only where Ng.L > 0.2 (a shadow map darkens every back-facing point). The table's
 * penumbra dimension is not baked: a hard shadow edge stays uncoloured. Specular, environment
 * and SH diffuse are the Lambert path's.
 * Its table, curvature and numbers go into the frame context, where the binder binds them. */
#include "pack/dm_pack_semantic.h"
#include "render/passes/dm_pass_preint.h"

static dm_result need(const dm_texture *t, const char *what, dm_error *err)
{
    if (t->texels) return DM_OK;
    return dm_fail(err, DM_ERR_MISMATCH, "assets: %s is missing, and subsurface (pre-integrated) needs it", what);
}

dm_result dmr_preint_check(const dmr_frame *f, const dm_render_assets *a, dm_error *err)
{
    if (!f->plan.pre_integrated) return DM_OK;
    dm_result rc = need(&a->preintegrated, "the pre-integrated table (sss.preintegrated)", err);
    if (rc == DM_OK) rc = need(&a->curvature, "the curvature map (sss.curvature)", err);
    if (rc == DM_OK && a->preintegrated.height < 2)
        rc = dm_fail(err, DM_ERR_RANGE, "assets: pre-integrated table of height %d, expected 2 or more",
                     a->preintegrated.height);
    if (rc == DM_OK && !(a->preint_curvature_max_per_mm >= 0.0f &&
                         a->preint_curvature_max_per_mm <= (float)DM_PACK_CURVATURE_MAX_PER_MM)) /* the pack's bound */
        rc = dm_fail(err, DM_ERR_RANGE, "assets: preint_curvature_max_per_mm = %g, expected 0 (default 1) or (0, %g]",
                     (double)a->preint_curvature_max_per_mm, DM_PACK_CURVATURE_MAX_PER_MM);
    return rc;
}

dm_result dmr_preint_upload(dmr_frame *f, void *st, const dm_render_assets *a, dm_error *err)
{
    (void)st;
    if (!f->plan.pre_integrated) return DM_OK;
    dmr_preint_inputs *in = &f->preint;
    dm_result rc = dmr_upload(f, &a->preintegrated, "preintegrated", false, GL_LINEAR, &in->table, err);
    if (rc == DM_OK) rc = dmr_upload(f, &a->curvature, "curvature", false, GL_LINEAR, &in->curvature, err);
    in->height = a->preintegrated.height;
    in->kmax = a->preint_curvature_max_per_mm > 0.0f ? a->preint_curvature_max_per_mm : 1.0f;
    const dm_profile *p = a->profile ? a->profile : &a->scene->profile;
    for (int c = 0; c < 3; ++c) {
        double sum = 0.0;
        for (int k = 0; k < p->count; ++k) sum += p->weight[k][c];
        in->blend[c] = sum > 0.0 ? (float)(1.0 - p->weight[0][c] / sum) : 0.0f;
    }
    return rc;
}
