/* dm_skin_spec.h — the physical skin's parameters as a command line or a scene gives them:
 * "key=value,…" over a preset or the defaults.
 *
 * Keys (core/dm_skin_keys.h names them; dm_skin_optics.h has the ranges, the laws and the
 * defaults):
 *   melanin       Cm, melanosome volume fraction of the epidermis      required
 *   eumelanin     βm, eumelanin share of the melanin                   required
 *   blood         Ch, blood volume fraction of the dermis              required
 *   oxygenation   γ, HbO2 share of the hemoglobin                      optional (0.75)
 *   epidermis-mm  epidermis thickness, mm                              optional (0.25)
 *   dermis-mm     dermis thickness, mm; 0 = semi-infinite              optional (0)
 *   eta           refractive index of the skin over air                optional (1.4)
 * e.g. "melanin=0.05,eumelanin=0.7,blood=0.01,epidermis-mm=0.1".
 */
#ifndef DM_SKIN_SPEC_H
#define DM_SKIN_SPEC_H

#include "bake/dm_skin_optics.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Parses spec into validated parameters (dm_skin_params_validate). `what` names the option
 * in messages. DM_ERR_INVALID_ARGUMENT for an unknown or repeated key, a value that is not
 * a number or a missing required key (the message names it); the range errors of
 * dm_skin_params_validate, naming the parameter and its range. */
dm_result dm_skin_spec_parse(const char *spec, const char *what, dm_skin_params *out, dm_error *err);

/* The same from pairs already read (a scene file's {"skin": {…}}): count keys (the names
 * above) and their values, over the preset `preset` (NULL: the defaults, and the required
 * keys must be there; a preset gives them). Errors as dm_skin_spec_parse's, and
 * dm_skin_preset's for an unknown preset. */
dm_result dm_skin_spec_pairs(const char *preset, const char *const *key, const double *value, int count,
                             const char *what, dm_skin_params *out, dm_error *err);

/* Writes p as a spec that dm_skin_spec_parse reads, every key, with `digits` significant
 * digits (17: reads back exactly; 6: for people), into buf of buf_size bytes (≥ 256). */
void dm_skin_spec_format(const dm_skin_params *p, int digits, char *buf, int buf_size);

#ifdef __cplusplus
}
#endif
#endif
