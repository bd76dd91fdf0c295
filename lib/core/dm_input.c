/* dm_input.c — regular files only, opened without blocking, read under a size cap
 * (dm_input.h). */
#include "core/dm_input.h"

#include <assert.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const struct {
    const char *what;
    uint64_t cap;
} kinds[DM_INPUT_KIND_COUNT] = {
#define DM_X_ROW(name, what, cap) {what, cap},
    DM_INPUT_KIND_TABLE(DM_X_ROW)
#undef DM_X_ROW
};

uint64_t dm_input_cap(dm_input_kind kind)
{
    assert((unsigned)kind < DM_INPUT_KIND_COUNT);
    return kinds[kind].cap;
}

const char *dm_input_kind_name(dm_input_kind kind)
{
    assert((unsigned)kind < DM_INPUT_KIND_COUNT);
    return kinds[kind].what;
}

/* "a FIFO", "a directory", ... for a file type that is not a regular file. */
static const char *type_name(mode_t mode)
{
    return S_ISDIR(mode)    ? "a directory"
           : S_ISFIFO(mode) ? "a FIFO (named pipe)"
           : S_ISCHR(mode)  ? "a character device"
           : S_ISBLK(mode)  ? "a block device"
           : S_ISSOCK(mode) ? "a socket"
                            : "not a regular file";
}

/* "16 MiB", "4 GiB", "17.3 MiB": sizes in messages. */
static void size_text(uint64_t bytes, char *out, size_t out_size)
{
    if (bytes >= DM_GIB)
        snprintf(out, out_size, bytes % DM_GIB ? "%.1f GiB" : "%.0f GiB", (double)bytes / (double)DM_GIB);
    else if (bytes >= DM_MIB)
        snprintf(out, out_size, bytes % DM_MIB ? "%.1f MiB" : "%.0f MiB", (double)bytes / (double)DM_MIB);
    else
        snprintf(out, out_size, "%llu bytes", (unsigned long long)bytes);
}

static dm_result not_regular(const char *path, mode_t mode, dm_input_kind kind, dm_error *err)
{
    char expected[128] = "";
    if (kind != DM_INPUT_ANY) snprintf(expected, sizeof expected, " (expected %s)", kinds[kind].what);
    if (S_ISDIR(mode) || S_ISFIFO(mode) || S_ISCHR(mode) || S_ISBLK(mode) || S_ISSOCK(mode))
        return dm_fail(err, DM_ERR_FILE_OPEN, "%s: is %s, not a regular file%s", path, type_name(mode), expected);
    return dm_fail(err, DM_ERR_FILE_OPEN, "%s: not a regular file%s", path, expected);
}

static dm_result over_cap(const char *path, uint64_t size, dm_input_kind kind, dm_error *err)
{
    char have[32], cap[32];
    size_text(size, have, sizeof have);
    size_text(kinds[kind].cap, cap, sizeof cap);
    return dm_fail(err, DM_ERR_FILE_OPEN, "%s: %s, more than the %s limit for %s (docs/files.md)", path, have, cap,
                   kinds[kind].what);
}

dm_result dm_input_open(const char *path, dm_input_kind kind, int *fd, uint64_t *size, dm_error *err)
{
    assert(path && fd && (unsigned)kind < DM_INPUT_KIND_COUNT);
    *fd = -1;
    if (size) *size = 0;
    if (!*path) return dm_fail(err, DM_ERR_FILE_OPEN, "an input path is empty, expected a file name");
    /* The name first, so that a device is not even opened (opening some has effects);
     * then the descriptor, which is what is read. */
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) return not_regular(path, st.st_mode, kind, err);
    int d = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (d < 0) return dm_fail(err, DM_ERR_FILE_OPEN, "%s: %s (cannot open)", path, strerror(errno));
    if (fstat(d, &st) != 0) {
        int e = errno;
        close(d);
        return dm_fail(err, DM_ERR_FILE_OPEN, "%s: %s", path, strerror(e));
    }
    if (!S_ISREG(st.st_mode)) {
        close(d);
        return not_regular(path, st.st_mode, kind, err);
    }
    if ((uint64_t)st.st_size > kinds[kind].cap) {
        close(d);
        return over_cap(path, (uint64_t)st.st_size, kind, err);
    }
    int flags = fcntl(d, F_GETFL);
    if (flags < 0 || fcntl(d, F_SETFL, flags & ~O_NONBLOCK) != 0) {
        int e = errno;
        close(d);
        return dm_fail(err, DM_ERR_FILE_OPEN, "%s: %s", path, strerror(e));
    }
    *fd = d;
    if (size) *size = (uint64_t)st.st_size;
    return DM_OK;
}

dm_result dm_input_check(const char *path, dm_input_kind kind, uint64_t *size, dm_error *err)
{
    int fd;
    dm_result r = dm_input_open(path, kind, &fd, size, err);
    if (r == DM_OK) close(fd);
    return r;
}

dm_result dm_input_read(const char *path, dm_input_kind kind, char **data, size_t *size, dm_error *err)
{
    assert(data && size);
    *data = NULL;
    *size = 0;
    int fd;
    uint64_t at_open;
    dm_result r = dm_input_open(path, kind, &fd, &at_open, err);
    if (r != DM_OK) return r;
    const uint64_t cap = kinds[kind].cap;
    if (at_open > (uint64_t)SIZE_MAX - 2) {
        close(fd);
        return over_cap(path, at_open, kind, err);
    }
    /* The size at open, plus one byte to see the end (or a file that grew). */
    size_t room = (size_t)at_open + 1, n = 0;
    char *buf = malloc(room + 1);
    if (!buf) {
        close(fd);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory for %llu bytes", path,
                       (unsigned long long)at_open);
    }
    for (;;) {
        if (n == room) { /* grew while read: go on up to the cap */
            if ((uint64_t)n > cap) break;
            size_t more = room < (1u << 20) ? room : (1u << 20);
            char *nb = realloc(buf, room + more + 1);
            if (!nb) {
                r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory at %zu bytes", path, n);
                break;
            }
            buf = nb;
            room += more;
        }
        ssize_t got = read(fd, buf + n, room - n);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) {
            r = dm_fail(err, errno == EISDIR ? DM_ERR_FILE_OPEN : DM_ERR_FILE_READ, "%s: read error (%s)", path,
                        strerror(errno));
            break;
        }
        if (got == 0) break;
        n += (size_t)got;
    }
    close(fd);
    if (r == DM_OK && (uint64_t)n > cap) r = over_cap(path, n, kind, err);
    if (r != DM_OK) {
        free(buf);
        return r;
    }
    buf[n] = '\0';
    *data = buf;
    *size = n;
    return DM_OK;
}
