/* dm_jread.h — the strict JSON reader every dermis JSON format is read with (the scene, the
 * pack manifest): unknown and repeated keys refused, types and ranges checked, and every error
 * naming the file, the JSON path ($.a.b[2].c), the value found and what was expected.
 * Each function returns false (NULL) after filling the reader's error; callers stop at the
 * first. Optional members (the _opt functions) leave *out alone when absent. */
#ifndef DM_JREAD_H
#define DM_JREAD_H

#include <stdbool.h>
#include <stdint.h>

#include <cJSON.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_jread {
    const char *where; /* message prefix: the file ("scene.json"), or "x.dpk: manifest" */
    dm_error *err;
    dm_result r; /* the first failure's code (DM_OK while none) */
} dm_jread;

enum { DM_JPATH_SIZE = 160 };

/* parent.key into out (truncated to DM_JPATH_SIZE). */
void dm_jread_path(char out[DM_JPATH_SIZE], const char *parent, const char *key);
/* "WHERE: JPATH: VALUE is not EXPECTED" with code. */
bool dm_jread_fail(dm_jread *c, dm_result code, const char *jpath, const cJSON *v, const char *expected);
/* Refuses members outside `allowed` (NULL-terminated; the message lists them) and members
 * given twice. */
bool dm_jread_keys(dm_jread *c, const cJSON *obj, const char *jpath, const char *const *allowed);
/* The member, or NULL (no error) when absent. */
const cJSON *dm_jread_get(const cJSON *obj, const char *key);
/* The member; absent: "WHERE: JPATH.KEY: missing, expected EXPECTED". */
const cJSON *dm_jread_required(dm_jread *c, const cJSON *obj, const char *jpath, const char *key,
                               const char *expected);
/* A member that must be an object; absent and optional: NULL with *ok = true. */
const cJSON *dm_jread_object(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, bool required,
                             bool *ok);
/* A required string member. */
const char *dm_jread_string(dm_jread *c, const cJSON *obj, const char *jpath, const char *key);
/* A required integer member in [lo, hi]. */
bool dm_jread_int64(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, int64_t lo, int64_t hi,
                    int64_t *out);
bool dm_jread_int32(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, int lo, int hi, int *out);

/* Optional members. */
bool dm_jread_double_opt(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, double lo, double hi,
                         double *out);
bool dm_jread_float_opt(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, double lo, double hi,
                        float *out);
/* An integer in [lo, hi]; odd_only refuses even values. */
bool dm_jread_int_opt(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, int lo, int hi,
                      bool odd_only, int *out);
bool dm_jread_bool_opt(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, bool *out);
/* Three finite numbers, each in [lo, hi]; nonzero refuses the zero vector. */
bool dm_jread_vec3_opt(dm_jread *c, const cJSON *obj, const char *jpath, const char *key, double lo, double hi,
                       bool nonzero, float out[3]);

#ifdef __cplusplus
}
#endif
#endif
