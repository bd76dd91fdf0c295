#include "bake/dm_lut_prov.h"

#include <string.h>

/* What every table's provenance starts with: the tool, the table, its size, its encoding. */
static void table_prov(dm_provenance *p, const char *tool, const char *table, int width, int height,
                       const char *encoding)
{
    dm_prov_init(p, tool);
    dm_prov_add_string(p, "table", table);
    dm_prov_add_int(p, "width", width);
    dm_prov_add_int(p, "height", height);
    dm_prov_add_string(p, "encoding", encoding);
}

void dm_lut_prov_beckmann(dm_provenance *p, const char *tool, int width, int height)
{
    table_prov(p, tool, "beckmann", width, height, "u8 0.5*D^0.1");
}

void dm_lut_prov_beckmann_exact(dm_provenance *p, const char *tool, int width, int height)
{
    table_prov(p, tool, "beckmann_exact", width, height, "f32 D");
}

void dm_lut_prov_directional(dm_provenance *p, const char *tool, const char *table, int width, int height, double f0,
                             int nodes)
{
    table_prov(p, tool, table, width, height, strcmp(table, "rho_dt") == 0 ? "f32 rho_dt" : "f32 scale,bias");
    dm_prov_add_double(p, "f0", f0);
    dm_prov_add_int(p, "nodes", nodes);
}

void dm_lut_prov_preintegrated(dm_provenance *p, const char *tool, int width, int height, double curvature_max_per_mm,
                               const char *profile_name, const char *profile_hash)
{
    table_prov(p, tool, "preintegrated", width, height, "f32 R,G,B D(N.L, curvature)");
    dm_prov_add_double(p, "curvature_max_per_mm", curvature_max_per_mm);
    dm_prov_add_string(p, "profile", profile_name);
    dm_prov_add_string(p, "profile_hash", profile_hash);
}

dm_result dm_lut_prov_match(const dm_provenance *have, const dm_provenance *want, const char *file, dm_error *err)
{
    if (strcmp(have->version, want->version) != 0)
        return dm_fail(err, DM_ERR_MISMATCH, "%s: baked by dermis %s, expected %s (re-bake it)", file, have->version,
                       want->version);
    for (int k = 0; k < want->param_count; ++k) {
        const dm_param *w = &want->params[k];
        const dm_param *h = dm_prov_find(have, w->name);
        if (!h)
            return dm_fail(err, DM_ERR_MISMATCH, "%s: provenance has no \"%s\", expected it", file, w->name);
        if (w->type == DM_PARAM_STRING) {
            if (h->type != DM_PARAM_STRING || strcmp(h->s, w->s) != 0)
                return dm_fail(err, DM_ERR_MISMATCH, "%s: %s is \"%s\", expected \"%s\"", file, w->name,
                               h->type == DM_PARAM_STRING ? h->s : "(a number)", w->s);
        } else if (h->type == DM_PARAM_STRING || h->d != w->d) {
            return dm_fail(err, DM_ERR_MISMATCH, "%s: %s is %.17g, expected %.17g", file, w->name,
                           h->type == DM_PARAM_STRING ? 0.0 : h->d, w->d);
        }
    }
    return DM_OK;
}
