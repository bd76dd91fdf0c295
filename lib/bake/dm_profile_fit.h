/* dm_profile_fit.h — fitting a sum of N Gaussians to a radial diffusion profile.
 *
 * The fit finds variances v_1 < … < v_N (mm², shared by R, G and B: the runtime's
 * incremental blur needs one chain of levels) and weights w_kc ≥ 0 minimising, per
 * channel c, the r-weighted squared error
 *     e_c = ∫₀^∞ r (R_c(r) − Σ_k w_kc G(v_k, r))² dr,
 * summed over the channels as Σ_c e_c / E_c with E_c = ∫ r R_c² dr, so every channel's
 * relative error counts the same (a dim blue channel as much as a bright red one).
 * Reported error per channel: sqrt(e_c / E_c) (0 = exact; 1 = no better than zero).
 * (Burley's profile uses the weight r² instead: see dm_source_kind.)
 *
 * Method (deterministic: no threads, no randomness, fixed iteration limits):
 *   - the integral is a composite Simpson rule in u = ln r over [r_min, r_max], plus the
 *     disc [0, r_min] (r_min = 1e-3 of the source's smallest length scale, r_max where
 *     r²R(r) has fallen below 1e-10 of its peak, capped at 1e6·r_min);
 *   - for fixed variances the weights are a non-negative least-squares problem per channel,
 *     solved exactly (Lawson–Hanson active set, on the Householder-QR reduced system);
 *   - the log-variances follow Levenberg–Marquardt on that variable-projection residual
 *     (Kaufman's Jacobian), from DM_FIT_STARTS geometric spacings over the scales seen in
 *     the source (R(0) and the second moment); the best is kept. Variances stay in
 *     [(10 r_min)², (r_max/4)²] and at least DM_FIT_MIN_RATIO apart.
 */
#ifndef DM_PROFILE_FIT_H
#define DM_PROFILE_FIT_H

#include <stdbool.h>

#include "bake/dm_skin_profile.h"
#include "core/dm_diffusion.h"
#include "core/dm_profile.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    DM_FIT_GAUSSIANS_DEFAULT = 6,
    DM_FIT_NODES_DEFAULT = 601, /* Simpson nodes in ln r (odd) */
    DM_FIT_NODES_MIN = 65,
    DM_FIT_NODES_MAX = 20001,
    DM_FIT_ITERATIONS_DEFAULT = 150, /* Levenberg–Marquardt steps per start */
    DM_FIT_STARTS = 4
};
#define DM_FIT_MIN_RATIO 1.2 /* smallest v_{k+1}/v_k */

/* What to fit: a sum of Gaussians (e.g. the gems3-skin preset, or a profile read from JSON),
 * a physical medium (dipole or multipole) or Burley's normalized diffusion.
 *
 * Burley's R(r) ∝ 1/r at r → 0: its mass is finite but ∫ r R² dr diverges (like ln 1/r_min),
 * so for DM_SOURCE_BURLEY the fit and its errors use the weight r² instead of r, i.e. the L2
 * error of the radial mass density r R(r): e_c = ∫₀^∞ (r R_c − r Σ w G)² dr, which is
 * finite. r_min is then 1e-6 of the smallest d = ℓ/S(A) and r_max at most 3000 of the
 * largest (the disc [0, r_min] counts r_min³ f(r_min): ~1e-6 of the norm). */
/* DM_SOURCE_SKIN: the physical skin of bake/dm_skin_profile.h, its per-channel R_c(r) held as
 * the dense representation (dm_skin_dense: 32 Gaussians per wavelength, exact to ~1e-6, with
 * signed channel weights, so a channel's negative lobes are there as they are); build it with
 * dm_profile_source_skin. */
typedef enum dm_source_kind { DM_SOURCE_GAUSSIANS, DM_SOURCE_MEDIUM, DM_SOURCE_BURLEY, DM_SOURCE_SKIN } dm_source_kind;

typedef struct dm_profile_source {
    dm_source_kind kind;
    dm_profile gaussians; /* DM_SOURCE_GAUSSIANS */
    dm_medium medium;     /* DM_SOURCE_MEDIUM */
    dm_burley burley;     /* DM_SOURCE_BURLEY */
    dm_skin_params skin;  /* DM_SOURCE_SKIN: the parameters … */
    dm_skin_dense skin_dense; /* … and their profile */
    double skin_total_rgb[3]; /* … and their exact colorimetric total R̃_c(0) (dm_skin_physics_report) */
} dm_profile_source;

/* A DM_SOURCE_SKIN source of the parameters p (validated here: dm_skin_params_validate's
 * errors, naming the parameter); DM_ERR_OUT_OF_MEMORY. */
dm_result dm_profile_source_skin(const dm_skin_params *p, dm_profile_source *out, dm_error *err);

/* A radial source as a command line names it (dermis-reference's --dipole, --multipole,
 * --burley): burley, "ALBEDO/MFP" (dm_burley_parse's two lists, e.g. "0.8,0.6,0.4/1,0.5,0.25");
 * otherwise a medium SPEC (dm_medium_parse) for the dipole, or for the multipole of a slab
 * thickness_mm thick with pair_count pairs (0: default). `what` names the option in errors.
 * DM_ERR_INVALID_ARGUMENT (and dm_*_parse's errors) for a malformed spec. */
dm_result dm_profile_source_parse(const char *spec, bool burley, bool multipole, double thickness_mm, int pair_count,
                                  const char *what, dm_profile_source *out, dm_error *err);
/* Checks the source (dm_profile_validate, dm_medium_validate or dm_burley_validate). */
dm_result dm_profile_source_validate(const dm_profile_source *s, const char *what, dm_error *err);
/* R(r) of the source per channel, mm⁻². */
void dm_profile_source_eval(const dm_profile_source *s, double r_mm, double rgb[3]);
/* Its total diffuse reflectance ∫ 2πr R dr in closed form (weight sums, the dipole /
 * multipole formulas, Burley's albedo, or the skin's colorimetric total R̃_c(0), exact: not
 * the dense representation's weight sums). */
void dm_profile_source_total(const dm_profile_source *s, double rgb[3]);

/* Zero-initialised = defaults. */
typedef struct dm_fit_options {
    int gaussian_count; /* 1..DM_PROFILE_MAX_GAUSSIANS; 0 = DM_FIT_GAUSSIANS_DEFAULT */
    int node_count;     /* odd, DM_FIT_NODES_MIN..MAX; 0 = DM_FIT_NODES_DEFAULT */
    int iterations;     /* LM steps per start, 1..10000; 0 = DM_FIT_ITERATIONS_DEFAULT */
} dm_fit_options;

typedef struct dm_fit_result {
    dm_profile profile;       /* the fit, in the source's units (not normalised to white) */
    double error_relative[3]; /* sqrt(e_c / E_c) per channel; 0 for an all-zero channel */
    double error_relative_max;
    double r_min_mm, r_max_mm; /* the integration range */
    int iterations;            /* accepted LM steps, all starts */
    int evaluations;           /* objective evaluations, all starts */
} dm_fit_result;

/* Fits opt->gaussian_count Gaussians to the source. The result's profile takes the name
 * given (may be NULL: ""). DM_ERR_RANGE/NON_FINITE for a bad source or option,
 * DM_ERR_EMPTY when every channel of the source is zero. */
dm_result dm_profile_fit(const dm_profile_source *s, const dm_fit_options *opt, const char *name,
                         dm_fit_result *out, dm_error *err);

/* The relative error per channel of any profile p against the source, by the same
 * quadrature as the fit (opt may be NULL for defaults). */
dm_result dm_profile_fit_error(const dm_profile_source *s, const dm_profile *p, const dm_fit_options *opt,
                               double error_relative[3], dm_error *err);

enum { DM_PROFILE_REPRESENT_MAX = 32 };

/* A dense representation of the source for the ground truth (dm_reference.h): gaussian_count
 * (2..DM_PROFILE_REPRESENT_MAX) Gaussians with fixed log-spaced standard deviations from a
 * quarter of the source's narrowest scale to a third of the radius holding all but 1e-4 of
 * its mass, weights ≥ 0 per channel by NNLS on the fit's quadrature (no variance search).
 * variance_mm2 and weight receive gaussian_count values (ascending variances, the source's
 * units: not normalised); rel_error the relative L2 error per channel, as the fit's. */
dm_result dm_profile_represent(const dm_profile_source *s, int gaussian_count, double *variance_mm2,
                               double (*weight)[3], double rel_error[3], dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
