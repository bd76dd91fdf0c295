/* dm_skin_spec.c — "key=value,…" to dm_skin_params (dm_skin_spec.h). */
#include "bake/dm_skin_spec.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { KEY_COUNT = 7, REQUIRED_COUNT = 3 };
static const char *const keys[KEY_COUNT] = {"melanin",     "eumelanin", "blood", "oxygenation",
                                            "epidermis-mm", "dermis-mm", "eta"};

static double *field(dm_skin_params *p, int k)
{
    double *f[KEY_COUNT] = {&p->melanin_fraction, &p->eumelanin_blend, &p->blood_fraction, &p->oxygenation,
                            &p->epidermis_mm,     &p->dermis_mm,       &p->eta};
    return f[k];
}

static int key_index(const char *key, size_t len)
{
    for (int k = 0; k < KEY_COUNT; ++k)
        if (strlen(keys[k]) == len && !strncmp(key, keys[k], len)) return k;
    return -1;
}

static dm_result unknown_key(const char *what, const char *key, int len, dm_error *err)
{
    return dm_fail(err, DM_ERR_INVALID_ARGUMENT,
                   "%s: unknown key '%.*s', expected melanin, eumelanin, blood, oxygenation, epidermis-mm, dermis-mm "
                   "or eta",
                   what, len, key);
}

dm_result dm_skin_spec_set(dm_skin_params *p, const char *key, double value, const char *what, dm_error *err)
{
    int k = key_index(key, strlen(key));
    if (k < 0) return unknown_key(what, key, (int)strlen(key), err);
    *field(p, k) = value;
    return DM_OK;
}

dm_result dm_skin_spec_parse(const char *spec, const char *what, dm_skin_params *out, dm_error *err)
{
    dm_skin_params p = dm_skin_params_default();
    int seen[KEY_COUNT] = {0};
    const char *s = spec;
    while (*s) {
        const char *eq = strchr(s, '='), *end = strchr(s, ',');
        if (!end) end = s + strlen(s);
        if (!eq || eq > end)
            return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: '%.*s' is not key=value (e.g. melanin=0.05)", what,
                           (int)(end - s), s);
        int k = key_index(s, (size_t)(eq - s));
        if (k < 0) return unknown_key(what, s, (int)(eq - s), err);
        if (seen[k]) return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: key '%s' given twice", what, keys[k]);
        seen[k] = 1;
        char *stop;
        errno = 0;
        double v = strtod(eq + 1, &stop);
        if (stop == eq + 1 || stop != end || errno == ERANGE)
            return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: %s = '%.*s', expected a number", what, keys[k],
                           (int)(end - eq - 1), eq + 1);
        *field(&p, k) = v;
        s = *end ? end + 1 : end;
    }
    for (int k = 0; k < REQUIRED_COUNT; ++k)
        if (!seen[k])
            return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: '%s=' is required (melanin, eumelanin and blood are)",
                           what, keys[k]);
    dm_result r = dm_skin_params_validate(&p, what, err);
    if (r == DM_OK) *out = p;
    return r;
}

void dm_skin_spec_format(const dm_skin_params *p, int digits, char *buf, int buf_size)
{
    int n = 0;
    buf[0] = '\0';
    for (int k = 0; k < KEY_COUNT && n >= 0 && n < buf_size; ++k)
        n += snprintf(buf + n, (size_t)(buf_size - n), "%s%s=%.*g", k ? "," : "", keys[k], digits,
                      *field((dm_skin_params *)p, k));
}
