/* dm_skin_spec.c — "key=value,…" to dm_skin_params (dm_skin_spec.h). */
#include "bake/dm_skin_spec.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_skin_keys.h"

enum { KEY_COUNT = DM_SKIN_KEY_COUNT };
#define keys dm_skin_keys

/* The parameter of key k (core/dm_skin_keys.h's order). */
static double *field(dm_skin_params *p, int k)
{
    double *f[KEY_COUNT] = {&p->melanin_fraction, &p->eumelanin_blend, &p->blood_fraction, &p->oxygenation,
                            &p->epidermis_mm,     &p->dermis_mm,       &p->eta};
    return f[k];
}

static dm_result unknown_key(const char *what, const char *key, int len, dm_error *err)
{
    return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: unknown key '%.*s', expected %s", what, len, key,
                   dm_skin_keys_text());
}

dm_result dm_skin_spec_pairs(const char *preset, const char *const *key, const double *value, int count,
                             const char *what, dm_skin_params *out, dm_error *err)
{
    dm_skin_params p = dm_skin_params_default();
    dm_result r;
    if (preset && (r = dm_skin_preset(preset, &p, err)) != DM_OK) {
        char inner[sizeof err->detail];
        snprintf(inner, sizeof inner, "%s", err ? err->detail : "");
        return dm_fail(err, r, "%s: %s", what, inner);
    }
    int seen[KEY_COUNT] = {0};
    for (int i = 0; i < count; ++i) {
        int k = dm_skin_key_index(key[i], strlen(key[i]));
        if (k < 0) return unknown_key(what, key[i], (int)strlen(key[i]), err);
        if (seen[k]) return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: key '%s' given twice", what, keys[k]);
        seen[k] = 1;
        *field(&p, k) = value[i];
    }
    for (int k = 0; !preset && k < DM_SKIN_KEY_REQUIRED_COUNT; ++k)
        if (!seen[k])
            return dm_fail(err, DM_ERR_INVALID_ARGUMENT,
                           "%s: '%s' is required (melanin, eumelanin and blood are, unless a preset is given)", what,
                           keys[k]);
    if ((r = dm_skin_params_validate(&p, what, err)) == DM_OK) *out = p;
    return r;
}

dm_result dm_skin_spec_parse(const char *spec, const char *what, dm_skin_params *out, dm_error *err)
{
    const char *names[KEY_COUNT + 1]; /* one more than the keys: a repeat reaches the check */
    double values[KEY_COUNT + 1];
    int n = 0;
    const char *s = spec;
    while (*s) {
        const char *eq = strchr(s, '='), *end = strchr(s, ',');
        if (!end) end = s + strlen(s);
        if (!eq || eq > end)
            return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: '%.*s' is not key=value (e.g. melanin=0.05)", what,
                           (int)(end - s), s);
        int k = dm_skin_key_index(s, (size_t)(eq - s));
        if (k < 0) return unknown_key(what, s, (int)(eq - s), err);
        if (n > KEY_COUNT)
            return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: more than %d keys: one is given twice", what, KEY_COUNT);
        char *stop;
        errno = 0;
        double v = strtod(eq + 1, &stop);
        if (stop == eq + 1 || stop != end || errno == ERANGE)
            return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: %s = '%.*s', expected a number", what, keys[k],
                           (int)(end - eq - 1), eq + 1);
        names[n] = keys[k];
        values[n++] = v;
        s = *end ? end + 1 : end;
    }
    return dm_skin_spec_pairs(NULL, names, values, n, what, out, err);
}

void dm_skin_spec_format(const dm_skin_params *p, int digits, char *buf, int buf_size)
{
    int n = 0;
    buf[0] = '\0';
    for (int k = 0; k < KEY_COUNT && n >= 0 && n < buf_size; ++k)
        n += snprintf(buf + n, (size_t)(buf_size - n), "%s%s=%.*g", k ? "," : "", keys[k], digits,
                      *field((dm_skin_params *)p, k));
}
