/* dm_pack_build_thin.c — the pack's thin-part maps (bake/dm_thin_map.h): "thin" at the
 * scene's irradiance size and "thin.half" at half of it (a renderer at N/2: dermis-view's
 * default), rays reaching 3 σ of the profile's widest Gaussian; each one RGBA32F texture of
 * N × 2N, candidate k of texel (i, j) in row k·N + j. */
#include <stdio.h>

#include "bake/dm_seam_map.h"
#include "bake/dm_thin_map.h"
#include "packer/dm_pack_build_impl.h"

dm_result dmpb_step_thin(dm_pack_build *j, dm_error *err)
{
    dm_result r = dmpb_ensure_mesh(j, err);
    const dm_profile *pf = &j->scene.profile;
    for (int half = 0; half < 2 && r == DM_OK; ++half) {
        const int n = j->scene.irradiance_size >> half;
        dm_thin_map_options o = {n, j->scene.mm_per_unit, dm_seam_map_reach_mm(pf->variance_mm2[pf->count - 1]),
                                 j->opt->threads};
        dm_thin_map map;
        dm_thin_map_stats st;
        if ((r = dm_thin_map_bake(&j->mesh, &o, &map, &st, err)) != DM_OK) return r;
        dm_provenance p;
        dmpb_mesh_prov(j, &p, "thin-part map: per texel up to 2 surfaces across a thin part or a fold (u, v, mm, 1); "
                              "candidate k in rows k*N..(k+1)*N-1");
        dm_prov_add_int(&p, "size", n);
        dm_prov_add_double(&p, "reach_mm", o.reach_mm);
        dm_thin_map_stats_prov(&st, &p);
        static const char *const ch[4] = {"u", "v", "mm", "candidate"};
        r = dmpb_add_mesh_rgba32f(j, half ? "thin.half" : "thin", n, DM_THIN_MAP_CANDIDATES * n, ch, map.texels, &p, err);
        if (r == DM_OK && !j->opt->quiet && j->opt->verbose)
            fprintf(stderr, "thin map at %d: %lld texels with one surface across, %lld with two, %lld dropped more\n", n,
                    (long long)st.one_candidate_texels, (long long)st.two_candidate_texels,
                    (long long)st.dropped_texels);
        dm_thin_map_free(&map);
    }
    return r;
}
