/* dm_uri.c — URIs confined to the referring file's folder (dm_uri.h). */
#define _XOPEN_SOURCE 700 /* realpath */
#include "core/dm_uri.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_file.h"

static int hex(int c)
{
    return c >= '0' && c <= '9'   ? c - '0'
           : c >= 'a' && c <= 'f' ? c - 'a' + 10
           : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                  : -1;
}

bool dm_uri_decode(const char *uri, char *out, size_t out_size)
{
    size_t n = 0;
    for (const char *p = uri; *p; ++p) {
        int c = (unsigned char)*p;
        if (c == '%' && hex(p[1]) >= 0 && hex(p[2]) >= 0) {
            c = hex(p[1]) * 16 + hex(p[2]);
            p += 2;
            if (c == 0) return false;
        }
        if (n + 1 >= out_size) return false;
        out[n++] = (char)c;
    }
    if (!out_size) return false;
    out[n] = '\0';
    return true;
}

/* "scheme:" at the start (RFC 3986: a letter, then letters, digits, '+', '-', '.'); a
 * Windows drive "C:" counts too: neither is a relative path. */
static bool has_scheme(const char *s)
{
    if (!isalpha((unsigned char)s[0])) return false;
    const char *p = s + 1;
    while (isalnum((unsigned char)*p) || *p == '+' || *p == '-' || *p == '.') ++p;
    return *p == ':';
}

/* A ".." component, with '/' or '\\' as separators. */
static bool has_parent(const char *s)
{
    for (const char *p = s; *p;) {
        size_t len = strcspn(p, "/\\");
        if (len == 2 && p[0] == '.' && p[1] == '.') return true;
        p += len;
        if (*p) ++p;
    }
    return false;
}

static dm_result refuse(dm_error *err, const char *referrer, const char *uri, const char *why)
{
    return dm_fail(err, DM_ERR_FILE_OPEN,
                   "%s: URI \"%.300s\": %s; a glTF may only name files in its own folder and below (docs/files.md)",
                   referrer, uri, why);
}

dm_result dm_uri_resolve(const char *referrer, const char *uri, bool decode, char *out, size_t out_size,
                         bool *missing, dm_error *err)
{
    if (missing) *missing = false;
    char name[4096];
    if (decode ? !dm_uri_decode(uri, name, sizeof name) : snprintf(name, sizeof name, "%s", uri) >= (int)sizeof name)
        return refuse(err, referrer, uri, "too long or holds %00");
    if (!name[0]) return refuse(err, referrer, uri, "empty");
    if (has_scheme(name)) return refuse(err, referrer, uri, "names a scheme (such as file:), not a relative path");
    if (name[0] == '/' || name[0] == '\\') return refuse(err, referrer, uri, "an absolute path");
    if (has_parent(name)) return refuse(err, referrer, uri, "a '..' component leaves the folder");
    char dir[4096];
    dm_dirname(referrer, dir, sizeof dir);
    if (snprintf(out, out_size, "%s/%s", dir, name) >= (int)out_size) return refuse(err, referrer, uri, "too long");
    /* Symbolic links: the real path must stay under the folder's real path. */
    char real_dir[PATH_MAX], real[PATH_MAX];
    if (!realpath(dir, real_dir))
        return dm_fail(err, DM_ERR_FILE_OPEN, "%s: its folder %s: %s", referrer, dir, strerror(errno));
    if (!realpath(out, real)) {
        int e = errno;
        if (missing) *missing = e == ENOENT;
        return dm_fail(err, DM_ERR_FILE_OPEN, "%s: URI \"%.300s\": %s: %s", referrer, uri, out, strerror(e));
    }
    size_t n = strlen(real_dir);
    bool root = n == 1 && real_dir[0] == '/';
    if (strncmp(real, real_dir, n) != 0 || (!root && real[n] != '/'))
        return refuse(err, referrer, uri, "resolves (through a symbolic link) outside the folder");
    return DM_OK;
}
