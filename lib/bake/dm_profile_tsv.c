/* dm_profile_tsv.c — a profile's numbers as tab-separated text (bake/dm_profile_tsv.h). */
#include "bake/dm_profile_tsv.h"

#include <math.h>
#include <stdio.h>

#include "bake/dm_skin_profile.h"
#include "core/dm_file.h"
#include "core/dm_math.h"

/* Opens path through a temporary and writes the provenance and the columns' description. */
static dm_result begin(dm_atomic_file *af, const char *path, const dm_provenance *prov, const char *columns,
                       dm_error *err)
{
    char json[64 * 1024];
    dm_result r = dm_prov_to_json(prov, json, sizeof json, err);
    if (r == DM_OK) r = dm_atomic_open(af, path, err);
    if (r == DM_OK) fprintf(af->fp, "# provenance %s\n# %s\n", json, columns);
    return r;
}

static dm_result end(dm_atomic_file *af, const char *path, dm_error *err)
{
    if (ferror(af->fp)) {
        dm_atomic_abort(af);
        return dm_fail(err, DM_ERR_FILE_WRITE, "%s: cannot write", path);
    }
    return dm_atomic_commit(af, err);
}

dm_result dm_profile_tsv_radial(const char *path, const dm_profile_source *s, const dm_profile *fit,
                                const dm_provenance *prov, dm_error *err)
{
    dm_atomic_file af;
    dm_result r = begin(&af, path, prov, "R(r) per linear-sRGB channel, 1/mm^2: the source (src_*) and the fitted "
                                         "Gaussians (fit_*), r in mm", err);
    if (r != DM_OK) return r;
    fprintf(af.fp, "r_mm\tsrc_r\tsrc_g\tsrc_b\tfit_r\tfit_g\tfit_b\n");
    const double lo = log(DM_PROFILE_TSV_R_MIN_MM), hi = log(DM_PROFILE_TSV_R_MAX_MM);
    for (int i = 0; i < DM_PROFILE_TSV_RADIAL_ROWS; ++i) {
        const double r_mm = exp(lo + (hi - lo) * i / (DM_PROFILE_TSV_RADIAL_ROWS - 1));
        double src[3], g[3] = {0, 0, 0};
        dm_profile_source_eval(s, r_mm, src);
        for (int k = 0; k < fit->count; ++k) {
            const double v = fit->variance_mm2[k];
            const double gauss = exp(-r_mm * r_mm / (2.0 * v)) / (2.0 * DM_PI * v);
            for (int c = 0; c < 3; ++c) g[c] += fit->weight[k][c] * gauss;
        }
        fprintf(af.fp, "%.9g\t%.9g\t%.9g\t%.9g\t%.9g\t%.9g\t%.9g\n", r_mm, src[0], src[1], src[2], g[0], g[1], g[2]);
    }
    return end(&af, path, err);
}

dm_result dm_profile_tsv_spectrum(const char *path, const dm_skin_params *p, const dm_provenance *prov, dm_error *err)
{
    dm_skin_report rep;
    dm_result r = dm_skin_physics_report(p, 0, &rep, err);
    if (r != DM_OK) return r;
    dm_atomic_file af;
    r = begin(&af, path, prov, "total diffuse reflectance per wavelength (R~(0)); flags: DM_SKIN_INVALID_* bits "
                               "where a layer left diffusion (docs/skin-model.md)", err);
    if (r != DM_OK) return r;
    fprintf(af.fp, "lambda_nm\ttotal\tflags\n");
    for (int i = 0; i < DM_SKIN_LAMBDA_COUNT; ++i)
        fprintf(af.fp, "%.9g\t%.9g\t%u\n", dm_skin_data[i].lambda_nm, rep.total_spectral[i], rep.invalid[i]);
    fprintf(af.fp, "# colorimetric total, linear sRGB (D65): %.9g %.9g %.9g\n", rep.total_rgb[0], rep.total_rgb[1],
            rep.total_rgb[2]);
    return end(&af, path, err);
}
