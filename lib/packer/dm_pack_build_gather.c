/* dm_pack_build_gather.c — the pack's thin gather (bake/dm_thin_gather.h) at the scene's
 * irradiance size: "gather.index" (RGBA32F, N × N) and "gather.taps" (RG32F, 4096 wide), and at
 * half of it ("gather.half.index", "gather.half.taps": a renderer at N/2, as thin.half), for the
 * profile's widest levels with σ ≥ 1 mm (up to four); texels share their taps in blocks of 2 × 2
 * or 4 × 4 where one run each would pass DM_THIN_GATHER_TAPS_MAX (the head at 2048²); nothing
 * when no level qualifies, or when even blocks of 4 × 4 pass it (a note on stderr). */
#include <stdio.h>

#include "bake/dm_thin_gather.h"
#include "packer/dm_pack_build_impl.h"

static dm_result gather_at(dm_pack_build *j, int half, dm_error *err)
{
    dm_result r;
    const dm_profile *pf = &j->scene.profile;
    dm_thin_gather_options o;
    dm_thin_gather_options_for(pf->variance_mm2, pf->count, j->scene.irradiance_size >> half, j->scene.mm_per_unit, &o);
    o.threads = j->opt->threads;
    if (o.level_count < 1) return DM_OK;
    dm_thin_gather g;
    dm_thin_gather_stats st;
    if ((r = dm_thin_gather_bake(&j->mesh, &o, &g, &st, err)) == DM_ERR_RANGE) {
        /* more taps than a pack should carry (at 2048² on the head): the pack goes without; the
         * renderer then takes the widest levels from the atlas blur and the thin-part map */
        if (!j->opt->quiet) fprintf(stderr, "note: %s: left out of the pack\n", err->detail);
        return DM_OK;
    }
    if (r != DM_OK) return r;
    dm_provenance p;
    dmpb_mesh_prov(j, &p, "thin gather: the widest levels as a 3-D sum over the surface's sites where a surface "
                          "facing away or a seam is near (first tap's row, taps of gathered level 0, of level 1, "
                          "first tap's column)");
    dm_prov_add_int(&p, "size", g.size);
    dm_prov_add_int(&p, "first_level", g.first_level);
    dm_prov_add_int(&p, "level_count", g.level_count);
    dm_prov_add_double(&p, "near_mm", o.near_mm);
    dm_prov_add_double(&p, "seam_mm", o.seam_mm);
    dm_prov_add_double(&p, "cluster_sigmas", DM_THIN_GATHER_CLUSTER_SIGMAS);
    dm_prov_add_double(&p, "split_sigmas", DM_THIN_GATHER_SPLIT_SIGMAS);
    dm_prov_add_double(&p, "coarse_cluster_sigmas", DM_THIN_GATHER_COARSE_CLUSTER_SIGMAS);
    dm_prov_add_double(&p, "reach_sigmas", DM_THIN_GATHER_REACH_SIGMAS);
    dm_thin_gather_stats_prov(&st, &p);
    static const char *const ch[4] = {"first_row", "taps0", "taps1", "first_col"};
    r = dmpb_add_mesh_rgba32f(j, half ? "gather.half.index" : "gather.index", g.size, g.size, ch, g.index, &p, err);
    if (r == DM_OK) {
        char src[200];
        snprintf(src, sizeof src, "baked from %.150s", dmpb_base_name(j->scene.mesh));
        dm_pack_entry d = dm_pack_texture_entry(half ? "gather.half.taps" : "gather.taps", DM_TEX_RG32F,
                                                DM_THIN_GATHER_TAPS_WIDTH, g.taps_rows);
        d.channel_count = 2;
        snprintf(d.channels[0], sizeof d.channels[0], "site_u");
        snprintf(d.channels[1], sizeof d.channels[1], "weight_v");
        r = dmpb_add(j, &d, g.taps, sizeof *g.taps * 2 * (size_t)DM_THIN_GATHER_TAPS_WIDTH * (size_t)g.taps_rows, &p,
                     src, err);
    }
    long long sites = 0;
    for (int k = 0; k < g.level_count; ++k) sites += (long long)st.sites[k];
    if (r == DM_OK && !j->opt->quiet && j->opt->verbose)
        fprintf(stderr, "thin gather at %d: %lld texels (%lld near a surface facing away, %lld near a seam) gather "
                "levels %d..%d in blocks of %d x %d, %lld taps over %lld sites\n", g.size, (long long)st.gathering_texels,
                (long long)st.thin_texels, (long long)st.seam_texels, g.first_level, g.first_level + g.level_count - 1,
                g.block, g.block, (long long)st.taps, sites);
    dm_thin_gather_free(&g);
    return r;
}

dm_result dmpb_step_gather(dm_pack_build *j, dm_error *err)
{
    dm_result r = dmpb_ensure_mesh(j, err);
    for (int half = 0; half < 2 && r == DM_OK; ++half) r = gather_at(j, half, err);
    return r;
}
