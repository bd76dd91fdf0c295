/* dm_prov.h — provenance: what made a file (STYLE.md §7).
 *
 * Every output file carries its tool, the dermis version, the hash of its input (when
 * it has one) and the full list of parameters with their types. The struct is a plain
 * value with fixed storage: no allocation, copy it freely. Writers turn it into typed
 * EXR attributes, PNG text chunks or a JSON object; readers fill it back.
 * The output path and the wall clock are deliberately absent: bakes are deterministic,
 * so the same inputs and options give byte-identical files wherever they are written.
 */
#ifndef DM_PROV_H
#define DM_PROV_H

#include <stdint.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_PROV_NAME_SIZE = 48, DM_PROV_STRING_SIZE = 512, DM_PROV_PARAM_MAX = 48 };

typedef enum dm_param_type { DM_PARAM_INT, DM_PARAM_DOUBLE, DM_PARAM_STRING } dm_param_type;

typedef struct dm_param {
    char name[DM_PROV_NAME_SIZE]; /* [a-z0-9_] */
    dm_param_type type;
    int64_t i;
    double d;
    char s[DM_PROV_STRING_SIZE];
} dm_param;

typedef struct dm_provenance {
    char tool[DM_PROV_NAME_SIZE];          /* e.g. "dermis-bake-lut" */
    char version[DM_PROV_NAME_SIZE];       /* DM_VERSION */
    char input_hash[DM_PROV_STRING_SIZE];  /* "xxh3-128:<hex>" of the input, or "" */
    int param_count;
    dm_param params[DM_PROV_PARAM_MAX];
} dm_provenance;

/* Clears p and sets its tool name and the current DM_VERSION. */
void dm_prov_init(dm_provenance *p, const char *tool);
/* Appends a parameter; asserts on overflow of DM_PROV_PARAM_MAX (a programming error).
 * Strings longer than DM_PROV_STRING_SIZE-1 are truncated. */
void dm_prov_add_int(dm_provenance *p, const char *name, int64_t value);
void dm_prov_add_double(dm_provenance *p, const char *name, double value);
void dm_prov_add_string(dm_provenance *p, const char *name, const char *value);
/* The parameter with that name, or NULL. */
const dm_param *dm_prov_find(const dm_provenance *p, const char *name);

/* Serialises p as one compact JSON object (doubles with 17 significant digits, so they
 * read back exactly) into out (out_size bytes). Returns DM_ERR_RANGE if it does not fit. */
dm_result dm_prov_to_json(const dm_provenance *p, char *out, size_t out_size, dm_error *err);
/* Parses what dm_prov_to_json wrote. `what` names the source in error messages. */
dm_result dm_prov_from_json(dm_provenance *p, const char *json, const char *what, dm_error *err);
/* The same from a parsed JSON node (a profile's or scene's "provenance" object): the values
 * as parsed, no printing and parsing again. */
struct cJSON;
dm_result dm_prov_from_cjson(dm_provenance *p, const struct cJSON *node, const char *what, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
