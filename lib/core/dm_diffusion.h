/* dm_diffusion.h — physical diffusion profiles R(r) from bulk optical parameters.
 *
 * Units: σa (absorption) and σs′ (reduced scattering) in mm⁻¹, r and thickness in mm,
 * η the relative index of refraction (medium over air, dimensionless). R(r) is the radial
 * diffuse reflectance in mm⁻² for unit incident flux, so ∫ 2πr R(r) dr is the total
 * diffuse reflectance (albedo) Rd, in [0, 1].
 *
 * Dipole — Jensen, Marschner, Levoy, Hanrahan, "A Practical Model for Subsurface Light
 * Transport", SIGGRAPH 2001, eq. 4–5:
 *   σt′ = σa + σs′, α′ = σs′/σt′, σtr = √(3 σa σt′), D = 1/(3σt′),
 *   Fdr = −1.440/η² + 0.710/η + 0.668 + 0.0636 η, A = (1 + Fdr)/(1 − Fdr),
 *   zr = 1/σt′, zv = zr + 4AD, dr = √(r² + zr²), dv = √(r² + zv²),
 *   R(r) = α′/4π [ zr (σtr dr + 1) e^(−σtr dr)/dr³ + zv (σtr dv + 1) e^(−σtr dv)/dv³ ].
 *   Rd = (α′/2) (1 + e^(−(4/3) A √(3(1−α′)))) e^(−√(3(1−α′)))   (closed form, eq. 6).
 *
 * Multipole for a slab of thickness d — Donner & Jensen, "Light Diffusion in Multi-Layered
 * Translucent Materials", SIGGRAPH 2005, eq. 8 (same η and so the same extrapolation
 * distance zb = 2AD on both faces):
 *   z_r,i = 2i(d + 2zb) + zr,  z_v,i = 2i(d + 2zb) − zr − 2zb,  i = −n..n,
 *   R(r) = α′/4π Σ_i [ z_r,i (σtr d_r,i + 1) e^(−σtr d_r,i)/d_r,i³
 *                     − z_v,i (σtr d_v,i + 1) e^(−σtr d_v,i)/d_v,i³ ],  d_·,i = √(r² + z_·,i²).
 *   Each term integrates in closed form (∫ 2πr z(σ d + 1)e^(−σd)/d³ dr = 2π sgn(z) e^(−σ|z|)),
 *   which gives dm_multipole_total. As d → ∞ only i = 0 remains: the dipole. As d → 0 the
 *   model tends to a finite limit, not to 0 (its source stays at depth 1/σt′ however thin
 *   the slab): diffusion theory does not hold for d σt′ ≪ 1, so treat thin-slab numbers
 *   as the model's, not as measurements.
 *
 * Burley normalized diffusion — Christensen & Burley, "Approximate Reflectance Profiles for
 * Efficient Subsurface Scattering", Pixar technical memo 15-04, 2015 (and SIGGRAPH 2015 talk):
 *   R(r) = A s (e^(−s r) + e^(−s r/3)) / (8π r),  s = 1/d,  d = ℓ / S(A),
 * with the per-channel surface albedo A ∈ [0, 1] and mean free path ℓ (mm). S(A) is the
 * paper's fit for the searchlight configuration parameterised by the mean free path:
 *   S(A) = 1.85 − A + 7 |A − 0.8|³
 * (its other fits, 1.9 − A + 3.5 (A − 0.8)² for diffuse surface transmission and
 * 3.5 + 100 (A − 0.33)⁴ for the diffuse mean free path, are not used). ∫ 2πr R dr = A exactly.
 * R has a 1/r singularity at r = 0 whose mass is finite: ∫₀^ε 2πr R dr ≈ A ε s/2 for
 * small ε; dm_burley_reflectance returns +inf at r = 0 (a quadrature must start at r > 0), and 0 for
 * r = +inf or A = 0.
 *
 * Hard cases (each tested): r = 0 is finite (dr = zr > 0); r huge or +inf gives 0, not
 * NaN; σa = 0 (σtr = 0) gives the r⁻³ tail and Rd = 1 for the dipole; η = 1 (Fdr ≈ 0.003);
 * thin and thick slabs. Invalid parameters are refused by dm_medium_validate, which the
 * R(r) functions assume has passed (they assert nothing and return NaN for NaN input).
 */
#ifndef DM_DIFFUSION_H
#define DM_DIFFUSION_H

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define DM_ETA_MIN 1.0 /* Jensen's Fdr polynomial is a fit for η ≥ 1 */
#define DM_ETA_MAX 3.0
#define DM_SIGMA_MAX_PER_MM 1e4 /* beyond this the diffusion scale is under 0.1 µm */
#define DM_THICKNESS_MAX_MM 1e4

enum {
    DM_MULTIPOLE_PAIRS_DEFAULT = 20, /* n: dipoles i = −n..n */
    DM_MULTIPOLE_PAIRS_MAX = 1000,
    DM_MEDIUM_NAME_SIZE = 32
};

typedef enum dm_diffusion_model { DM_MODEL_DIPOLE, DM_MODEL_MULTIPOLE } dm_diffusion_model;

/* A homogeneous medium, per RGB channel. Zero-initialised is invalid (σs′ must be > 0). */
typedef struct dm_medium {
    char name[DM_MEDIUM_NAME_SIZE];  /* preset name, or "" when given by numbers */
    dm_diffusion_model model;
    double sigma_a_per_mm[3];        /* ≥ 0, ≤ DM_SIGMA_MAX_PER_MM */
    double sigma_s_prime_per_mm[3];  /* > 0, ≤ DM_SIGMA_MAX_PER_MM */
    double eta;                      /* [DM_ETA_MIN, DM_ETA_MAX] */
    double thickness_mm;             /* multipole only: (0, DM_THICKNESS_MAX_MM] */
    int pair_count;                  /* multipole only: 1..DM_MULTIPOLE_PAIRS_MAX; 0 = default */
} dm_medium;

/* Refuses negative, NaN, infinite or out-of-range parameters with a message that names
 * `what`, the field, the channel, the value and the accepted range. */
dm_result dm_medium_validate(const dm_medium *m, const char *what, dm_error *err);

/* Measured media of Jensen et al. 2001 (Figure 5's table, η = 1.3, σa and σs′ in mm⁻¹):
 * "skin1", "skin2", "marble", "wholemilk", "skimmilk", "apple", "ketchup". Fills the dipole
 * model; set model/thickness_mm afterwards for a slab. DM_ERR_INVALID_ARGUMENT (message
 * lists the names) for an unknown name. */
dm_result dm_medium_preset(const char *name, dm_medium *m, dm_error *err);
/* The preset names, NULL-terminated, for --help. */
const char *const *dm_medium_preset_names(void);

/* A medium from a command-line SPEC: a preset name (dm_medium_preset), 3 numbers
 * "sa,ss,eta" (every channel alike) or 7 "saR,saG,saB,ssR,ssG,ssB,eta" (σa, σs′ in mm⁻¹),
 * with the model, slab thickness (multipole) and pair count (0 = default) given; validated.
 * `what` (the option, e.g. "--dipole") prefixes messages. DM_ERR_INVALID_ARGUMENT for a
 * malformed SPEC, dm_medium_validate's codes for values out of range. */
dm_result dm_medium_parse(const char *spec, dm_diffusion_model model, double thickness_mm, int pair_count,
                          const char *what, dm_medium *m, dm_error *err);

/* Fdr, the average diffuse Fresnel reflectance for η ≥ 1 (Jensen 2001, eq. 5's fit). */
double dm_fresnel_diffuse_reflectance(double eta);

/* One channel's dipole R(r), mm⁻²; parameters as validated by dm_medium_validate. */
double dm_dipole(double sigma_a, double sigma_s_prime, double eta, double r_mm);
/* Its closed-form total diffuse reflectance ∫ 2πr R dr. */
double dm_dipole_total(double sigma_a, double sigma_s_prime, double eta);
/* One channel's multipole R(r) for a slab of thickness_mm with dipoles i = −pairs..pairs. */
double dm_multipole(double sigma_a, double sigma_s_prime, double eta, double thickness_mm, int pairs, double r_mm);
/* Its total diffuse reflectance, summed term by term in closed form (same truncation). */
double dm_multipole_total(double sigma_a, double sigma_s_prime, double eta, double thickness_mm, int pairs);

/* R(r) of a validated medium for all three channels (its model and pair_count). */
void dm_medium_eval(const dm_medium *m, double r_mm, double rgb[3]);
/* Rd of a validated medium for all three channels. */
void dm_medium_total(const dm_medium *m, double rgb[3]);

/* A Burley normalized-diffusion profile, per RGB channel. */
typedef struct dm_burley {
    double albedo[3]; /* A: [0, 1] */
    double mfp_mm[3]; /* ℓ: (0, DM_MFP_MAX_MM] */
} dm_burley;
#define DM_MFP_MAX_MM 1e4

/* Refuses NaN, infinite or out-of-range albedo / mean free path, naming `what`, the field,
 * the channel, the value and the range. */
dm_result dm_burley_validate(const dm_burley *b, const char *what, dm_error *err);
/* A Burley profile from two command-line lists, each 1 number (grey) or 3 "R,G,B";
 * validated. `what` (e.g. "--burley") prefixes messages. DM_ERR_INVALID_ARGUMENT for a
 * malformed list, DM_ERR_RANGE / DM_ERR_NON_FINITE for values out of range. */
dm_result dm_burley_parse(const char *albedo, const char *mfp, const char *what, dm_burley *b, dm_error *err);
/* S(A) = 1.85 − A + 7|A − 0.8|³, dimensionless (d = ℓ / S). */
double dm_burley_shape(double albedo);
/* d = ℓ / S(A), mm: the profile's length scale (R ∝ e^(−r/d) + e^(−r/3d)). */
double dm_burley_scale_mm(double albedo, double mfp_mm);
/* One channel's R(r), mm⁻²: +inf at r = 0 when A > 0, 0 when A = 0 or r = +inf. */
double dm_burley_reflectance(double albedo, double mfp_mm, double r_mm);
/* R(r) of a validated profile for all three channels. */
void dm_burley_eval(const dm_burley *b, double r_mm, double rgb[3]);
/* ∫ 2πr R dr per channel in closed form: the albedo. */
void dm_burley_total(const dm_burley *b, double rgb[3]);
/* ∫₀^ρ 2πr R dr in closed form: A (1 − e^(−ρ/d)/4 − 3e^(−ρ/3d)/4), the mass within ρ. */
double dm_burley_mass_within(double albedo, double mfp_mm, double rho_mm);

#ifdef __cplusplus
}
#endif
#endif
