#include "core/dm_file.h"

#include <assert.h>
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void dm_dirname(const char *path, char *out, size_t out_size)
{
    const char *slash = strrchr(path, '/');
    if (!slash) {
        snprintf(out, out_size, ".");
    } else if (slash == path) {
        snprintf(out, out_size, "/");
    } else {
        snprintf(out, out_size, "%.*s", (int)(slash - path), path);
    }
}

dm_result dm_atomic_begin(dm_atomic_file *af, const char *path, dm_error *err)
{
    assert(af && path);
    memset(af, 0, sizeof *af);
    if (!*path) return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "output path is empty");
    if (strlen(path) >= sizeof af->path)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%.64s...: output path too long", path);
    snprintf(af->path, sizeof af->path, "%s", path);
    snprintf(af->tmp_path, sizeof af->tmp_path, "%s.tmp.%ld", path, (long)getpid());
    char dir[4096];
    dm_dirname(path, dir, sizeof dir);
    if (access(dir, W_OK) != 0)
        return dm_fail(err, DM_ERR_FILE_WRITE, "%s: folder '%s' is not writable (%s)", path, dir, strerror(errno));
    return DM_OK;
}

dm_result dm_atomic_open(dm_atomic_file *af, const char *path, dm_error *err)
{
    dm_result r = dm_atomic_begin(af, path, err);
    if (r != DM_OK) return r;
    af->fp = fopen(af->tmp_path, "wb");
    if (!af->fp) return dm_fail(err, DM_ERR_FILE_WRITE, "%s: %s", af->tmp_path, strerror(errno));
    return DM_OK;
}

dm_result dm_atomic_commit(dm_atomic_file *af, dm_error *err)
{
    if (af->fp) {
        int bad = fflush(af->fp) != 0 || ferror(af->fp);
        bad |= fclose(af->fp) != 0;
        af->fp = NULL;
        if (bad) {
            int e = errno;
            dm_atomic_abort(af);
            return dm_fail(err, DM_ERR_FILE_WRITE, "%s: write failed (%s)", af->path, strerror(e));
        }
    }
    int fd = open(af->tmp_path, O_RDONLY);
    if (fd < 0) {
        int e = errno;
        dm_atomic_abort(af);
        return dm_fail(err, DM_ERR_FILE_WRITE, "%s: temporary file vanished (%s)", af->path, strerror(e));
    }
    int sync_bad = fsync(fd) != 0;
    close(fd);
    if (sync_bad || rename(af->tmp_path, af->path) != 0) {
        int e = errno;
        dm_atomic_abort(af);
        return dm_fail(err, DM_ERR_FILE_WRITE, "%s: cannot finish writing (%s)", af->path, strerror(e));
    }
    af->tmp_path[0] = '\0';
    return DM_OK;
}

void dm_atomic_abort(dm_atomic_file *af)
{
    if (af->fp) {
        fclose(af->fp);
        af->fp = NULL;
    }
    if (af->tmp_path[0]) {
        unlink(af->tmp_path);
        af->tmp_path[0] = '\0';
    }
}

dm_result dm_read_file(const char *path, char **data, size_t *size, dm_error *err)
{
    *data = NULL;
    *size = 0;
    FILE *f = fopen(path, "rb");
    if (!f) return dm_fail(err, DM_ERR_FILE_OPEN, "%s: %s", path, strerror(errno));
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    if (!buf) {
        fclose(f);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    size_t got;
    while ((got = fread(buf + n, 1, cap - n, f)) > 0) {
        n += got;
        if (n == cap) {
            char *nb = realloc(buf, cap * 2 + 1);
            if (!nb) {
                free(buf);
                fclose(f);
                return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory at %zu bytes", path, cap);
            }
            buf = nb;
            cap *= 2;
        }
    }
    int bad = ferror(f);
    fclose(f);
    if (bad) {
        free(buf);
        return dm_fail(err, DM_ERR_FILE_READ, "%s: read error", path);
    }
    buf[n] = '\0';
    *data = buf;
    *size = n;
    return DM_OK;
}
