/* dm_mesh_check_file (dm_mesh.h): strict pre-passes over what OpenMesh's readers trust. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/dm_mesh.h"

/* Parses up to `max` numbers from s; returns how many parsed, -1 if one is not finite
 * as a float (OpenMesh reads floats: a value beyond FLT_MAX makes its stream fail and
 * drops the element). A number is a whole token of decimal digits, sign, point and
 * exponent that strtof consumes entirely ("inf" and "nan" are not finite; hex floats
 * and "1e" are not numbers to OpenMesh's reader either). */
static int numbers(const char *s, double *out, int max)
{
    int n = 0;
    while (n < max) {
        while (*s && isspace((unsigned char)*s)) ++s;
        if (!*s) break;
        size_t len = strcspn(s, " \t\r\n\v\f");
        char *end;
        float v = strtof(s, &end);
        if (end != s + len) break;
        if (!isfinite(v)) return -1;
        if (strspn(s, "0123456789+-.eE") < len) break;
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

static dm_result check_obj(const char *path, FILE *fp, dm_error *err)
{
    static const char *const kind[3] = {"vertex", "texture coordinate", "normal"};
    long long count[3] = {0, 0, 0}; /* v, vt, vn so far */
    char *line = NULL;
    size_t cap = 0;
    long long lineno = 0;
    dm_result r = DM_OK;
    ssize_t len;
    while (r == DM_OK && (len = getline(&line, &cap, fp)) >= 0) {
        ++lineno;
        /* Text only: a NUL ends the line for this check but not for OpenMesh's reader,
         * and the two disagree on which other control characters are white space. */
        for (ssize_t i = 0; i < len && r == DM_OK; ++i) {
            unsigned char c = (unsigned char)line[i];
            if ((c < 0x20 && c != '\t' && c != '\r' && c != '\n') || c == 0x7f)
                r = dm_fail(err, DM_ERR_FORMAT, "%s:%lld: control character 0x%02X, expected a text line", path,
                            lineno, c);
        }
        if (r != DM_OK) break;
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
    return r;
}

static dm_result check_ply(const char *path, FILE *fp, dm_error *err)
{
    enum { HEADER_MAX = 65536 };
    char *buf = malloc(HEADER_MAX + 1);
    if (!buf) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    size_t n = fread(buf, 1, HEADER_MAX, fp);
    buf[n] = '\0';
    dm_result r = DM_OK;
    if (n < 4 || memcmp(buf, "ply", 3) != 0 || (buf[3] != '\n' && buf[3] != '\r'))
        r = dm_fail(err, DM_ERR_FORMAT, "%s: does not start with a 'ply' line, expected a PLY header", path);
    else {
        /* "end_header" at the start of a line; NUL bytes end the search (binary junk). */
        const char *p = buf;
        int found = 0;
        while ((p = strstr(p, "end_header")) && !found) {
            found = p > buf && (p[-1] == '\n' || p[-1] == '\r');
            ++p;
        }
        if (!found)
            r = dm_fail(err, DM_ERR_FORMAT, "%s: no 'end_header' line in the first %d bytes, expected a PLY header",
                        path, HEADER_MAX);
    }
    free(buf);
    return r;
}

dm_result dm_mesh_check_file(const char *path, dm_error *err)
{
    const char *dot = strrchr(path, '.');
    int obj = dot && strlen(dot) == 4 && tolower((unsigned char)dot[1]) == 'o' &&
              tolower((unsigned char)dot[2]) == 'b' && tolower((unsigned char)dot[3]) == 'j';
    int ply = dot && strlen(dot) == 4 && tolower((unsigned char)dot[1]) == 'p' &&
              tolower((unsigned char)dot[2]) == 'l' && tolower((unsigned char)dot[3]) == 'y';
    if (!obj && !ply) return DM_OK;
    FILE *fp = fopen(path, "rb");
    if (!fp) return dm_fail(err, DM_ERR_FILE_OPEN, "%s: cannot open (%s)", path, strerror(errno));
    dm_result r = obj ? check_obj(path, fp, err) : check_ply(path, fp, err);
    fclose(fp);
    return r;
}
