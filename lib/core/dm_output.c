/* dm_output.c — an output checked before the work (dm_output.h). */
#include "core/dm_output.h"

#include <assert.h>
#include <errno.h>
#include <fcntl.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/dm_cli.h"
#include "core/dm_file.h"

int dm_output_extension(const char *path, const char *const *extensions)
{
    size_t n = strlen(path);
    for (int k = 0; extensions && extensions[k]; ++k) {
        size_t m = strlen(extensions[k]);
        if (n > m && strcasecmp(path + n - m, extensions[k]) == 0) return k;
    }
    return -1;
}

/* ".png or .exr" */
static void extension_list(const char *const *extensions, char *out, size_t out_size)
{
    size_t n = 0;
    out[0] = '\0';
    for (int k = 0; extensions[k] && n < out_size; ++k)
        n += (size_t)snprintf(out + n, out_size - n, "%s%s", k == 0 ? "" : extensions[k + 1] ? ", " : " or ",
                              extensions[k]);
}

/* The nearest folder of path that exists (path's own folder, or an ancestor of it when
 * folders are missing, which the write creates). */
static dm_result existing_folder(const char *option, const char *path, char *dir, size_t dir_size, dm_error *err)
{
    dm_dirname(path, dir, dir_size);
    for (;;) {
        struct stat st;
        if (stat(dir, &st) == 0) {
            if (S_ISDIR(st.st_mode)) return DM_OK;
            return dm_fail(err, DM_ERR_FILE_WRITE, "%s %s: '%s' is not a folder", option, path, dir);
        }
        if (errno != ENOENT)
            return dm_fail(err, DM_ERR_FILE_WRITE, "%s %s: folder '%s': %s", option, path, dir, strerror(errno));
        char up[4096];
        dm_dirname(dir, up, sizeof up);
        if (!strcmp(up, dir)) return dm_fail(err, DM_ERR_FILE_WRITE, "%s %s: no folder of it exists", option, path);
        snprintf(dir, dir_size, "%s", up);
    }
}

/* Creates and removes a probe file in dir: what the write itself will need. */
static dm_result probe(const char *option, const char *path, const char *dir, dm_error *err)
{
    static int counter;
    for (int attempt = 0; attempt < 100; ++attempt) {
        char name[4200];
        snprintf(name, sizeof name, "%s/.dermis-probe.%ld.%d", dir, (long)getpid(), counter++);
        int fd = open(name, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
        if (fd >= 0) {
            close(fd);
            unlink(name); /* ours: made just now with O_EXCL */
            return DM_OK;
        }
        if (errno != EEXIST)
            return dm_fail(err, DM_ERR_FILE_WRITE, "%s %s: cannot write in the folder '%s' (%s)", option, path, dir,
                           strerror(errno));
    }
    return dm_fail(err, DM_ERR_FILE_WRITE, "%s %s: cannot make a file in the folder '%s'", option, path, dir);
}

dm_result dm_output_check(const char *option, const char *path, const char *const *extensions,
                          const char *const *inputs, int input_count, int *format, dm_error *err)
{
    assert(option && path && extensions && extensions[0]);
    if (format) *format = -1;
    if (!*path) return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: the output name is empty", option);
    int k = dm_output_extension(path, extensions);
    if (k < 0) {
        char list[256];
        extension_list(extensions, list, sizeof list);
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s %s: expected a name ending in %s (any case): the extension "
                       "names the format written", option, path, list);
    }
    struct stat out;
    if (stat(path, &out) == 0) {
        if (!S_ISREG(out.st_mode))
            return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s %s: exists and is not a regular file (%s), expected a "
                           "file name to write", option, path,
                           S_ISDIR(out.st_mode) ? "a directory" : "a device, FIFO or socket");
        for (int i = 0; i < input_count; ++i) {
            struct stat in;
            if (inputs[i] && stat(inputs[i], &in) == 0 && in.st_dev == out.st_dev && in.st_ino == out.st_ino)
                return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s %s: the same file as the input %s: writing it "
                               "would destroy the input; choose another output name", option, path, inputs[i]);
        }
    }
    char dir[4096];
    dm_result r = existing_folder(option, path, dir, sizeof dir, err);
    if (r == DM_OK) r = probe(option, path, dir, err);
    if (r == DM_OK && format) *format = k;
    return r;
}

int dm_output_check_cli(const char *option, const char *path, const char *const *extensions,
                        const char *const *inputs, int input_count, int *format)
{
    dm_error err = {0};
    dm_result r = dm_output_check(option, path, extensions, inputs, input_count, format, &err);
    if (r == DM_OK) return 0;
    fprintf(stderr, "error: %s\n", err.detail);
    return r == DM_ERR_FILE_WRITE ? DM_EXIT_SAVE : DM_EXIT_USAGE;
}
