#include "bake/dm_profile_json.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_file.h"
#include "core/dm_sbuf.h"

static void put_source(dm_sbuf *b, const dm_profile_source *s, const char *preset)
{
    double total[3];
    dm_profile_source_total(s, total);
    const char *model = s->kind == DM_SOURCE_GAUSSIANS             ? "gaussians"
                        : s->kind == DM_SOURCE_BURLEY           ? "burley"
                        : s->kind == DM_SOURCE_SKIN             ? "skin"
                        : s->medium.model == DM_MODEL_MULTIPOLE ? "multipole"
                                                                 : "dipole";
    dm_sbuf_put(b, "{\n    \"model\": \"%s\",\n    \"preset\": ", model);
    dm_sbuf_str(b, preset);
    if (s->kind == DM_SOURCE_GAUSSIANS) {
        dm_sbuf_put(b, ",\n    \"gaussians\": ");
        dm_profile_put_gaussians(b, &s->gaussians, "    ", 0);
    } else if (s->kind == DM_SOURCE_SKIN) { /* bake/dm_skin_optics.h: the two-layer spectral model */
        const dm_skin_params *k = &s->skin;
        const char *const names[7] = {"melanin_fraction", "eumelanin_blend", "blood_fraction", "oxygenation",
                                      "epidermis_mm",     "dermis_mm",       "eta"};
        const double v[7] = {k->melanin_fraction, k->eumelanin_blend, k->blood_fraction, k->oxygenation,
                             k->epidermis_mm,     k->dermis_mm,       k->eta};
        for (int i = 0; i < 7; ++i) {
            dm_sbuf_put(b, ",\n    \"%s\": ", names[i]);
            dm_sbuf_num(b, v[i]);
        }
    } else if (s->kind == DM_SOURCE_BURLEY) { /* Christensen & Burley 2015, S(A) for ℓ (searchlight) */
        dm_sbuf_put(b, ",\n    \"albedo\": ");
        dm_sbuf_rgb(b, s->burley.albedo);
        dm_sbuf_put(b, ",\n    \"mfp_mm\": ");
        dm_sbuf_rgb(b, s->burley.mfp_mm);
    } else {
        const dm_medium *m = &s->medium;
        dm_sbuf_put(b, ",\n    \"sigma_a_per_mm\": ");
        dm_sbuf_rgb(b, m->sigma_a_per_mm);
        dm_sbuf_put(b, ",\n    \"sigma_s_prime_per_mm\": ");
        dm_sbuf_rgb(b, m->sigma_s_prime_per_mm);
        dm_sbuf_put(b, ",\n    \"eta\": ");
        dm_sbuf_num(b, m->eta);
        if (m->model == DM_MODEL_MULTIPOLE) {
            dm_sbuf_put(b, ",\n    \"thickness_mm\": ");
            dm_sbuf_num(b, m->thickness_mm);
            dm_sbuf_put(b, ",\n    \"pairs\": %d", m->pair_count ? m->pair_count : DM_MULTIPOLE_PAIRS_DEFAULT);
        }
    }
    dm_sbuf_put(b, ",\n    \"total_reflectance_rgb\": ");
    dm_sbuf_rgb(b, total);
    dm_sbuf_put(b, "\n  }");
}

dm_result dm_profile_doc_to_json(const dm_profile_doc *doc, char **json, dm_error *err)
{
    *json = NULL;
    dm_result r = dm_profile_validate(doc->profile, "profile to write", err);
    if (r != DM_OK) return r;
    const dm_profile *p = doc->profile;
    dm_sbuf b = {0};
    dm_sbuf_put(&b, "{\n  \"format\": \"dermis-profile\",\n  \"version\": 1,\n  \"name\": ");
    dm_sbuf_str(&b, p->name);
    dm_sbuf_put(&b, ",\n  \"normalized\": %s,\n  \"gaussians\": ", doc->normalized ? "true" : "false");
    dm_profile_put_gaussians(&b, p, "  ", 1);
    dm_sbuf_put(&b, ",\n  \"blur_passes\": %d,\n  \"total_reflectance_rgb\": ", dm_profile_blur_passes(p->count));
    dm_sbuf_rgb(&b, doc->total_reflectance);
    if (doc->has_error) {
        dm_sbuf_put(&b, ",\n  \"error\": {\n    \"measure\": \"sqrt(integral r (R - sum G)^2 dr / integral r R^2 dr), per "
                "channel, before normalisation\",\n    \"relative_rgb\": ");
        dm_sbuf_rgb(&b, doc->error_relative);
        dm_sbuf_put(&b, ",\n    \"relative_max\": ");
        dm_sbuf_num(&b, doc->error_relative_max);
        dm_sbuf_put(&b, "\n  }");
    }
    if (doc->source) {
        dm_sbuf_put(&b, ",\n  \"source\": ");
        put_source(&b, doc->source, doc->source_preset);
    }
    if (doc->provenance) {
        char prov[64 * 1024];
        r = dm_prov_to_json(doc->provenance, prov, sizeof prov, err);
        if (r != DM_OK) {
            free(b.s);
            return r;
        }
        dm_sbuf_put(&b, ",\n  \"provenance\": %s", prov);
    }
    dm_sbuf_put(&b, "\n}\n");
    if (b.failed) {
        free(b.s);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "profile '%s': cannot build its JSON", p->name);
    }
    *json = b.s;
    return DM_OK;
}

dm_result dm_profile_write(const char *path, const dm_profile_doc *doc, dm_error *err)
{
    char *json = NULL;
    dm_result r = dm_profile_doc_to_json(doc, &json, err);
    if (r != DM_OK) return r;
    dm_atomic_file af;
    r = dm_atomic_open(&af, path, err);
    if (r == DM_OK) {
        size_t n = strlen(json);
        if (fwrite(json, 1, n, af.fp) != n) {
            dm_atomic_abort(&af);
            r = dm_fail(err, DM_ERR_FILE_WRITE, "%s: short write of %zu bytes", path, n);
        } else {
            r = dm_atomic_commit(&af, err);
        }
    }
    free(json);
    return r;
}
