#include "core/dm_file.h"

#include "core/dm_input.h"

#include <assert.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

/* --- cleanup on signals ---------------------------------------------------------------
 * Slots: state 0 free, 2 being written, 1 live. The handler reads only live slots, and
 * unlink is async-signal-safe; a name that no longer exists (already renamed) is harmless. */
enum { CLEANUP_SLOTS = 32 };
static char g_cleanup_path[CLEANUP_SLOTS][4200];
static atomic_int g_cleanup_state[CLEANUP_SLOTS];
static const int g_signals[] = {SIGINT, SIGTERM, SIGHUP};
static struct sigaction g_previous[3];
static pthread_once_t g_install_once = PTHREAD_ONCE_INIT;

static void on_signal(int sig)
{
    int saved = errno;
    for (int k = 0; k < CLEANUP_SLOTS; ++k)
        if (atomic_load(&g_cleanup_state[k]) == 1) unlink(g_cleanup_path[k]);
    for (int s = 0; s < 3; ++s)
        if (g_signals[s] == sig) sigaction(sig, &g_previous[s], NULL);
    errno = saved;
    raise(sig); /* delivered on return, by the previous disposition (default: terminate) */
}

static void install_handlers(void)
{
    for (int s = 0; s < 3; ++s) {
        struct sigaction old;
        if (sigaction(g_signals[s], NULL, &old) != 0) continue;
        if (!(old.sa_flags & SA_SIGINFO) && old.sa_handler == SIG_IGN) continue; /* nohup, background job */
        g_previous[s] = old;
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_signal;
        sigemptyset(&sa.sa_mask);
        for (int t = 0; t < 3; ++t) sigaddset(&sa.sa_mask, g_signals[t]);
        sa.sa_flags = SA_RESTART;
        sigaction(g_signals[s], &sa, NULL);
    }
}

int dm_cleanup_register(const char *path)
{
    assert(path);
    pthread_once(&g_install_once, install_handlers);
    if (strlen(path) >= sizeof g_cleanup_path[0]) return -1;
    for (int k = 0; k < CLEANUP_SLOTS; ++k) {
        int expected = 0;
        if (atomic_compare_exchange_strong(&g_cleanup_state[k], &expected, 2)) {
            memcpy(g_cleanup_path[k], path, strlen(path) + 1);
            atomic_store(&g_cleanup_state[k], 1);
            return k;
        }
    }
    return -1;
}

void dm_cleanup_unregister(int slot)
{
    if (slot >= 0 && slot < CLEANUP_SLOTS) atomic_store(&g_cleanup_state[slot], 0);
}

dm_result dm_mkdir_p(const char *dir, dm_error *err)
{
    char buf[4096];
    if (snprintf(buf, sizeof buf, "%s", dir) >= (int)sizeof buf)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%.64s...: folder path too long", dir);
    for (char *p = buf + 1;; ++p) {
        if (*p != '/' && *p != '\0') continue;
        char c = *p;
        *p = '\0';
        struct stat st;
        if (stat(buf, &st) != 0) {
            if (mkdir(buf, 0777) != 0 && errno != EEXIST)
                return dm_fail(err, DM_ERR_FILE_WRITE, "%s: cannot create the folder '%s' (%s)", dir, buf,
                               strerror(errno));
        } else if (!S_ISDIR(st.st_mode)) {
            return dm_fail(err, DM_ERR_FILE_WRITE, "%s: '%s' is not a folder", dir, buf);
        }
        if (c == '\0') break;
        *p = c;
    }
    return DM_OK;
}

/* Removes "<base>.tmp.<PID>" in dir whose process is gone (a run killed by SIGKILL). */
static void remove_stale(const char *dir, const char *base)
{
    DIR *d = opendir(dir);
    if (!d) return;
    size_t base_len = strlen(base);
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        const char *n = e->d_name;
        if (strncmp(n, base, base_len) != 0 || strncmp(n + base_len, ".tmp.", 5) != 0) continue;
        const char *digits = n + base_len + 5;
        if (!*digits || strspn(digits, "0123456789") != strlen(digits) || strlen(digits) > 9) continue;
        long pid = atol(digits);
        if (pid <= 0 || pid == (long)getpid()) continue;
        if (kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue; /* alive (or not ours to judge) */
        char full[8400];
        snprintf(full, sizeof full, "%s/%s", dir, n);
        if (unlink(full) == 0)
            fprintf(stderr, "note: removed %s, left by an interrupted run (process %ld)\n", full, pid);
        else
            fprintf(stderr, "warning: %s is left by an interrupted run (process %ld): delete it (%s)\n", full, pid,
                    strerror(errno));
    }
    closedir(d);
}

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
    af->cleanup_slot = -1;
    if (!*path) return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "output path is empty");
    if (strlen(path) >= sizeof af->path)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%.64s...: output path too long", path);
    snprintf(af->path, sizeof af->path, "%s", path);
    snprintf(af->tmp_path, sizeof af->tmp_path, "%s.tmp.%ld", path, (long)getpid());
    char dir[4096];
    dm_dirname(path, dir, sizeof dir);
    dm_result r = dm_mkdir_p(dir, err);
    if (r != DM_OK) return r;
    if (access(dir, W_OK) != 0)
        return dm_fail(err, DM_ERR_FILE_WRITE, "%s: folder '%s' is not writable (%s)", path, dir, strerror(errno));
    const char *slash = strrchr(path, '/');
    remove_stale(dir, slash ? slash + 1 : path);
    af->cleanup_slot = dm_cleanup_register(af->tmp_path);
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
    dm_cleanup_unregister(af->cleanup_slot);
    af->cleanup_slot = -1;
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
    dm_cleanup_unregister(af->cleanup_slot);
    af->cleanup_slot = -1;
}

dm_result dm_read_file(const char *path, char **data, size_t *size, dm_error *err)
{
    return dm_input_read(path, DM_INPUT_ANY, data, size, err);
}
