/* dm_skin_mc.h — Monte Carlo photon transport in a layered slab: the independent reference
 * the layered diffusion model (issue #30) is validated against.
 *
 * The method of MCML (L. Wang, S. L. Jacques, L. Zheng, "MCML — Monte Carlo modeling of light
 * transport in multi-layered tissues", Computer Methods and Programs in Biomedicine 47 (1995)
 * 131–146), written from the paper's description:
 *  - a pencil beam at normal incidence at r = 0; the specular reflection of the top surface,
 *    ((n_above − n₁)/(n_above + n₁))², is reported apart and the photon packet enters with
 *    weight 1 − Rsp;
 *  - free paths s = −ln ξ in units of mean free paths, spent layer by layer: a step that
 *    reaches an interface stops there and keeps its remainder (× μt of the next layer);
 *  - implicit absorption: at each interaction the weight drops by w·μa/μt (tallied in the
 *    layer), then the packet scatters by Henyey–Greenstein;
 *  - Russian roulette below weight 1e-4: survives with chance 0.1 at 10× its weight;
 *  - every interface (top, bottom and between layers of different n) reflects or refracts
 *    by the unpolarised Fresnel reflectance at the packet's angle (one ξ decides, the packet
 *    is not split), with total internal reflection; Snell's law turns the direction.
 * Units: lengths in mm, μa and μs in mm⁻¹ (MCML's cm inputs ÷ 10). Layer 0 is on top.
 *
 * Determinism: photons run in fixed-size batches; batch b draws from its own xoshiro256**
 * stream seeded by splitmix64 from (seed, b); each batch tallies into its own slot and the
 * slots are summed in batch order. Same desc (seed, photon_count, batch size) → the same
 * bytes for any thread_count. Standard errors are the spread of the batch means.
 *
 * Guards: μs = 0 (pure absorber: Beer–Lambert), μa = 0 (photons end only by leaving: a packet
 * that takes more than step_limit steps stops and its weight is reported in `unfinished`),
 * g = ±1, layers thinner than 1 nm, matched and mismatched indices: none gives NaN or Inf.
 * Energy: specular + diffuse_reflectance + transmittance + Σ absorbed + unfinished = 1
 * within MC noise (roulette conserves weight only on average).
 */
#ifndef DM_SKIN_MC_H
#define DM_SKIN_MC_H

#include <stdint.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    DM_SKIN_MC_LAYERS_MAX = 8,
    DM_SKIN_MC_BATCH_DEFAULT = 1000,      /* photons per batch */
    DM_SKIN_MC_RADIAL_BINS_MAX = 1 << 16
};
#define DM_SKIN_MC_STEP_LIMIT_DEFAULT 1000000u /* steps (interactions + interface hits) per photon */
#define DM_SKIN_MC_ROULETTE_WEIGHT 1e-4
#define DM_SKIN_MC_ROULETTE_CHANCE 0.1
#define DM_SKIN_MC_INDEX_MAX 10.0

/* One homogeneous layer. */
typedef struct dm_skin_mc_layer {
    double n;            /* refractive index, [1, DM_SKIN_MC_INDEX_MAX] */
    double mu_a_per_mm;  /* absorption, ≥ 0, finite */
    double mu_s_per_mm;  /* scattering (not reduced), ≥ 0, finite */
    double g;            /* Henyey–Greenstein anisotropy, [−1, 1] */
    double thickness_mm; /* > 0; +INFINITY (semi-infinite) for the last layer only */
} dm_skin_mc_layer;

/* What to simulate. Zero-initialised fields take the defaults named. */
typedef struct dm_skin_mc_desc {
    const dm_skin_mc_layer *layers; /* layer_count entries, top first */
    int layer_count;                /* 1..DM_SKIN_MC_LAYERS_MAX */
    double n_above;                 /* ambient index above the stack; 0 = 1.0 */
    double n_below;                 /* ambient index below the stack; 0 = 1.0 */
    uint64_t photon_count;          /* ≥ 1 */
    uint64_t seed;
    int batch_photon_count;         /* photons per batch; 0 = DM_SKIN_MC_BATCH_DEFAULT */
    double dr_mm;                   /* radial bin width, > 0 when radial_bin_count > 0 */
    int radial_bin_count;           /* 0..DM_SKIN_MC_RADIAL_BINS_MAX; bin i is [i·dr, (i+1)·dr) */
    int thread_count;               /* 0 = dm_cpu_count() */
    uint32_t step_limit;            /* per photon; 0 = DM_SKIN_MC_STEP_LIMIT_DEFAULT */
} dm_skin_mc_desc;

/* Results: fractions of the incident power (dimensionless) unless marked. */
typedef struct dm_skin_mc_result {
    double specular;                /* Rsp, exact (not sampled) */
    double diffuse_reflectance;     /* Rd: weight leaving the top */
    double diffuse_reflectance_se;
    double transmittance;           /* Tt: weight leaving the bottom (0 for a semi-infinite stack) */
    double transmittance_se;
    double absorbed[DM_SKIN_MC_LAYERS_MAX]; /* A per layer */
    double absorbed_se[DM_SKIN_MC_LAYERS_MAX];
    double unfinished;              /* weight of packets stopped by step_limit (or lost) */
    uint64_t unfinished_photon_count;
    double reflectance_beyond_bins; /* part of Rd that left at r ≥ radial_bin_count · dr */
    uint64_t batch_count;
    /* Caller-owned arrays of radial_bin_count doubles (may be NULL when there are no bins):
     * Rd(r) per unit area, mm⁻², bin weight / (N · annulus area), and its standard error.
     * Σ Rd(r_i) · π((i+1)² − i²) dr² + reflectance_beyond_bins = Rd. */
    double *rd_r_per_mm2;
    double *rd_r_se_per_mm2;
} dm_skin_mc_result;

/* Refuses a stack or desc out of range (NaN, negative, n < 1, |g| > 1, thickness ≤ 0, an
 * infinite layer that is not the last, no photons, bins without a width), naming `what`,
 * the layer, the field, the value and the accepted range. */
dm_result dm_skin_mc_validate(const dm_skin_mc_desc *desc, const char *what, dm_error *err);

/* Runs the simulation. out->rd_r_per_mm2 and out->rd_r_se_per_mm2 must each hold
 * desc->radial_bin_count doubles (or be NULL to skip them); every other field of out is
 * overwritten. Allocates batch_count × (radial_bin_count + layer_count + 5) doubles of
 * scratch, freed before it returns. DM_ERR_* of dm_skin_mc_validate, DM_ERR_OUT_OF_MEMORY. */
dm_result dm_skin_mc_run(const dm_skin_mc_desc *desc, dm_skin_mc_result *out, dm_error *err);

/* Unpolarised Fresnel reflectance for a ray going from index n_i into n_t with cos θi =
 * cos_i ∈ [0, 1]; 1 beyond the critical angle. */
double dm_skin_mc_fresnel(double n_i, double n_t, double cos_i);

#ifdef __cplusplus
}
#endif
#endif
