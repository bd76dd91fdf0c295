/* dm_mesh_check_obj (dm_mesh.h): a strict pre-pass over an OBJ's v, vt, vn and f lines. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_mesh.h"

/* Parses up to `max` numbers from s; returns how many parsed, -1 if one is not finite. */
static int numbers(const char *s, double *out, int max)
{
    int n = 0;
    while (n < max) {
        while (*s && isspace((unsigned char)*s)) ++s;
        if (!*s) break;
        char *end;
        double v = strtod(s, &end);
        if (end == s) break;
        if (!isfinite(v)) return -1;
        out[n++] = v;
        s = end;
    }
    return n;
}

/* Parses one index field ("", or a signed integer) into *idx (0 when empty). */
static int index_field(const char **s, long long *idx)
{
    *idx = 0;
    if (**s == '/' || **s == '\0' || isspace((unsigned char)**s)) return 1;
    char *end;
    errno = 0;
    long long v = strtoll(*s, &end, 10);
    if (end == *s || errno) return 0;
    *idx = v;
    *s = end;
    return 1;
}

static int resolve(long long idx, long long count, long long *out)
{
    long long r = idx < 0 ? count + idx + 1 : idx;
    *out = r;
    return idx != 0 && r >= 1 && r <= count;
}

dm_result dm_mesh_check_obj(const char *path, dm_error *err)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return dm_fail(err, DM_ERR_FILE_OPEN, "%s: cannot open (%s)", path, strerror(errno));
    static const char *const kind[3] = {"vertex", "texture coordinate", "normal"};
    long long count[3] = {0, 0, 0}; /* v, vt, vn so far */
    char *line = NULL;
    size_t cap = 0;
    long long lineno = 0;
    dm_result r = DM_OK;
    while (r == DM_OK && getline(&line, &cap, fp) >= 0) {
        ++lineno;
        const char *s = line;
        while (*s && isspace((unsigned char)*s)) ++s;
        const char *kw = s;
        while (*s && !isspace((unsigned char)*s)) ++s;
        size_t kl = (size_t)(s - kw);
        double v[4];
        if ((kl == 1 && kw[0] == 'v') || (kl == 2 && kw[0] == 'v' && (kw[1] == 't' || kw[1] == 'n'))) {
            int which = kl == 1 ? 0 : kw[1] == 't' ? 1 : 2;
            int need = which == 1 ? 2 : 3;
            int got = numbers(s, v, need);
            if (got < 0)
                r = dm_fail(err, DM_ERR_NON_FINITE, "%s:%lld: %s %lld has a NaN or infinite value, expected finite numbers",
                            path, lineno, kind[which], count[which] + 1);
            else if (got < need)
                r = dm_fail(err, DM_ERR_FORMAT, "%s:%lld: %s %lld has %d numbers, expected %d", path, lineno,
                            kind[which], count[which] + 1, got, need);
            ++count[which];
        } else if (kl == 1 && kw[0] == 'f') {
            int corners = 0;
            for (;;) {
                while (*s && isspace((unsigned char)*s)) ++s;
                if (!*s) break;
                long long idx[3] = {0, 0, 0};
                int ok = index_field(&s, &idx[0]) && idx[0] != 0;
                for (int k = 1; k < 3 && ok && *s == '/'; ++k) {
                    ++s;
                    ok = index_field(&s, &idx[k]);
                }
                if (!ok || (*s && !isspace((unsigned char)*s))) {
                    r = dm_fail(err, DM_ERR_FORMAT, "%s:%lld: face corner %d is not v, v/vt, v//vn or v/vt/vn", path,
                                lineno, corners + 1);
                    break;
                }
                for (int k = 0; k < 3 && r == DM_OK; ++k) {
                    long long abs_idx;
                    if (idx[k] != 0 && !resolve(idx[k], count[k], &abs_idx))
                        r = dm_fail(err, DM_ERR_RANGE, "%s:%lld: face corner %d uses %s %lld, expected 1..%lld", path,
                                    lineno, corners + 1, kind[k], idx[k] < 0 ? abs_idx : idx[k], count[k]);
                }
                if (r != DM_OK) break;
                ++corners;
            }
            if (r == DM_OK && corners < 3)
                r = dm_fail(err, DM_ERR_FORMAT, "%s:%lld: face with %d corners, expected 3 or more", path, lineno,
                            corners);
        }
    }
    if (r == DM_OK && ferror(fp)) r = dm_fail(err, DM_ERR_FILE_READ, "%s: read error", path);
    free(line);
    fclose(fp);
    return r;
}
