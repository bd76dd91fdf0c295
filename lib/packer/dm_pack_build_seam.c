/* dm_pack_build_seam.c — the pack's seam map (bake/dm_seam_map.h): at the scene's irradiance
 * size, reaching 3 σ of the profile's widest Gaussian beyond each chart's edge. */
#include <stdio.h>

#include "bake/dm_seam_map.h"
#include "packer/dm_pack_build_impl.h"

dm_result dmpb_step_seam(dm_pack_build *j, dm_error *err)
{
    dm_result r = dmpb_ensure_mesh(j, err);
    if (r != DM_OK) return r;
    const int n = j->scene.irradiance_size;
    const dm_profile *pf = &j->scene.profile;
    dm_seam_map_options o = {n, j->scene.mm_per_unit, dm_seam_map_reach_mm(pf->variance_mm2[pf->count - 1])};
    dm_seam_map map;
    dm_seam_map_stats st;
    if ((r = dm_seam_map_bake(&j->mesh, &o, &map, &st, err)) != DM_OK) return r;
    dm_provenance p;
    dmpb_mesh_prov(j, &p, "seam map: per gutter texel the UV where the surface continues (u, v, 1, mm beyond)");
    dm_prov_add_int(&p, "size", n);
    dm_prov_add_double(&p, "reach_mm", o.reach_mm);
    dm_seam_map_stats_prov(&st, &p);
    static const char *const ch[4] = {"u", "v", "continued", "mm"};
    r = dmpb_add_mesh_rgba32f(j, "seam", n, n, ch, map.texels, &p, err);
    if (r == DM_OK && !j->opt->quiet && j->opt->verbose)
        fprintf(stderr, "seam map: %lld seam edges, %lld gutter texels continued, %lld lost\n",
                (long long)st.seam_edges, (long long)st.continued_texels, (long long)st.lost_texels);
    dm_seam_map_free(&map);
    return r;
}
