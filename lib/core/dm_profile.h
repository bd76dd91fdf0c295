/* dm_profile.h — diffusion profiles as sums of Gaussians (DESIGN.md "Six Gaussians").
 *
 * G(v, r) = exp(−r²/2v) / (2πv), v in mm². A profile is R(r) = Σ_k w_k G(v_k, r) per
 * RGB channel, variances ascending and shared by the channels (the runtime's incremental
 * blur needs that: level k is level k−1 blurred by v_k − v_{k−1}).
 *
 * JSON form (written by dermis-fit-profile, read here):
 *   { "format": "dermis-profile", "version": 1, "name": "gems3-skin",
 *     "gaussians": [ {"variance_mm2": 0.0064, "weights": [0.233, 0.455, 0.649]}, ... ],
 *     "error": {...}, "source": {...}, "provenance": {...} }
 * Only "gaussians" is needed to use a profile; the rest is information.
 */
#ifndef DM_PROFILE_H
#define DM_PROFILE_H

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_PROFILE_MAX_GAUSSIANS = 8, DM_PROFILE_NAME_SIZE = 64 };

typedef struct dm_profile {
    char name[DM_PROFILE_NAME_SIZE];
    int count;                                      /* 1..DM_PROFILE_MAX_GAUSSIANS */
    double variance_mm2[DM_PROFILE_MAX_GAUSSIANS];  /* strictly ascending, > 0 */
    double weight[DM_PROFILE_MAX_GAUSSIANS][3];     /* ≥ 0, per RGB channel */
} dm_profile;

/* The d'Eon/Luebke six-Gaussian skin profile of DESIGN.md ("gems3-skin"). */
void dm_profile_gems3_skin(dm_profile *p);

/* Checks the invariants above; names `what` and the offending index in the message. */
dm_result dm_profile_validate(const dm_profile *p, const char *what, dm_error *err);

/* Parses the JSON form; `what` (usually the file name) prefixes error messages, which
 * name the JSON path, the value and what was expected. */
dm_result dm_profile_from_json(const char *json, const char *what, dm_profile *p, dm_error *err);
/* Reads a profile JSON file. */
dm_result dm_profile_read(const char *path, dm_profile *p, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
