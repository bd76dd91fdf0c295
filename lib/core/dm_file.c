#include "core/dm_file.h"

#include "core/dm_input.h"

#include <assert.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/xattr.h>
#include <time.h>
#include <unistd.h>

/* --- cleanup on signals ---------------------------------------------------------------
 * Slots: state 0 free, 2 being written, 1 live, 3 a temporary being created (its thread has
 * the signals blocked, but a process-directed signal may be taken by another thread: that
 * handler waits until the creation ends, live or failed). The handler unlinks only live
 * slots, and unlink is async-signal-safe; a name that no longer exists (already renamed) is
 * harmless. */
enum { CLEANUP_SLOTS = 32 };
static char g_cleanup_path[CLEANUP_SLOTS][4200];
static atomic_int g_cleanup_state[CLEANUP_SLOTS];
static const int g_signals[] = {SIGINT, SIGTERM, SIGHUP};
static struct sigaction g_previous[3];
static pthread_once_t g_install_once = PTHREAD_ONCE_INIT;

static void on_signal(int sig)
{
    int saved = errno;
    for (int k = 0; k < CLEANUP_SLOTS; ++k) {
        while (atomic_load(&g_cleanup_state[k]) == 3) nanosleep(&(struct timespec){0, 1000000}, NULL);
        if (atomic_load(&g_cleanup_state[k]) == 1) unlink(g_cleanup_path[k]);
    }
    /* another thread may open a temporary again by name right after (OpenEXR's
     * exr_start_write opens it with O_CREAT) and make it anew before the process ends: a
     * second pass a moment later takes that one too (seen under the sanitizer, 1 run in 15) */
    nanosleep(&(struct timespec){0, 20000000}, NULL);
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

/* A free slot holding path in state `state` (1 live, 3 being created), or -1. */
static int cleanup_take(const char *path, int state)
{
    pthread_once(&g_install_once, install_handlers);
    if (strlen(path) >= sizeof g_cleanup_path[0]) return -1;
    for (int k = 0; k < CLEANUP_SLOTS; ++k) {
        int expected = 0;
        if (atomic_compare_exchange_strong(&g_cleanup_state[k], &expected, 2)) {
            memcpy(g_cleanup_path[k], path, strlen(path) + 1);
            atomic_store(&g_cleanup_state[k], state);
            return k;
        }
    }
    return -1;
}

int dm_cleanup_register(const char *path)
{
    assert(path);
    return cleanup_take(path, 1);
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

/* --- temporaries: their names and the proof that one is a dead run's own -----------------
 * (The reasons are in dm_file.h.) The marker is the extended attribute TMP_XATTR holding
 * "dermis-tmp 1 HOST PID START", START the process's start time in clock ticks since boot
 * (field 22 of /proc/PID/stat), which tells a dead run from a live process that got its
 * PID again. */
#define TMP_XATTR "user.dermis.tmp"

static bool process_start(long pid, unsigned long long *ticks)
{
    char path[64], buf[1024];
    snprintf(path, sizeof path, "/proc/%ld/stat", pid);
    FILE *f = fopen(path, "r");
    if (!f) return false;
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    char *p = strrchr(buf, ')'), *save = NULL; /* the command name may hold spaces */
    int field = 2;
    for (char *t = p ? strtok_r(p + 1, " ", &save) : NULL; t; t = strtok_r(NULL, " ", &save))
        if (++field == 22) return *ticks = strtoull(t, NULL, 10), true;
    return false;
}

static void tmp_marker(long pid, char *out, size_t size)
{
    char host[256] = "";
    unsigned long long start = 0;
    gethostname(host, sizeof host - 1);
    process_start(pid, &start);
    snprintf(out, size, "dermis-tmp 1 %s %ld %llu", host, pid, start);
}

/* The PID of "<base>.tmp.<PID>.dermis" or "<base>.tmp.<PID>-<K>.dermis", else 0. */
static long tmp_name_pid(const char *name, const char *base)
{
    size_t base_len = strlen(base);
    if (strncmp(name, base, base_len) != 0 || strncmp(name + base_len, ".tmp.", 5) != 0) return 0;
    const char *p = name + base_len + 5;
    size_t digits = strspn(p, "0123456789");
    if (digits == 0 || digits > 9) return 0;
    long pid = atol(p);
    p += digits;
    if (*p == '-' && (digits = strspn(p + 1, "0123456789")) > 0 && digits <= 3) p += 1 + digits;
    return strcmp(p, ".dermis") == 0 ? pid : 0;
}

/* Removes the temporaries of target `base` in dir that are provably a dead run's own. */
static void remove_stale(const char *dir, const char *base)
{
    DIR *d = opendir(dir);
    if (!d) return;
    char mine[512];
    tmp_marker(0, mine, sizeof mine); /* "dermis-tmp 1 HOST 0 0": the host part */
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        long pid = tmp_name_pid(e->d_name, base);
        if (pid <= 0 || pid == (long)getpid()) continue;
        char full[8400], mark[512];
        snprintf(full, sizeof full, "%s/%s", dir, e->d_name);
        ssize_t n = getxattr(full, TMP_XATTR, mark, sizeof mark - 1);
        bool unsupported = n < 0 && (errno == ENOTSUP || errno == EOPNOTSUPP);
        if (n < 0 && !unsupported) continue; /* no marker: not a dermis temporary, whatever its name */
        char host[256] = "";
        long marked_pid = 0;
        unsigned long long start = 0;
        if (n >= 0) {
            mark[n] = '\0';
            char want_host[256] = "";
            if (sscanf(mark, "dermis-tmp 1 %255s %ld %llu", host, &marked_pid, &start) != 3 ||
                sscanf(mine, "dermis-tmp 1 %255s", want_host) != 1 || strcmp(host, want_host) != 0 ||
                marked_pid != pid)
                continue; /* another host's (a shared folder) or not made as its name says */
        }
        unsigned long long now_start = 0;
        bool alive = kill((pid_t)pid, 0) == 0 || errno != ESRCH;
        if (alive && n >= 0 && process_start(pid, &now_start) && now_start != start) alive = false; /* PID reused */
        if (alive) continue;
        if (unsupported)
            fprintf(stderr, "warning: %s looks left by an interrupted run (process %ld), but this file system keeps "
                            "no marker to prove it: delete it if it is\n", full, pid);
        else if (unlink(full) == 0)
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
    char dir[4096];
    dm_dirname(path, dir, sizeof dir);
    dm_result r = dm_mkdir_p(dir, err);
    if (r != DM_OK) return r;
    const char *slash = strrchr(path, '/');
    remove_stale(dir, slash ? slash + 1 : path);
    /* O_EXCL: the temporary is a new file, never one that was there (the user's own). The
     * signals wait while it is made and registered: none can fall between the two. */
    pthread_once(&g_install_once, install_handlers);
    sigset_t block, old;
    sigemptyset(&block);
    for (int s = 0; s < 3; ++s) sigaddset(&block, g_signals[s]);
    pthread_sigmask(SIG_BLOCK, &block, &old);
    /* the slot is taken first, "being created": a signal another thread takes meanwhile waits
     * for the outcome (on_signal) instead of missing the new file */
    snprintf(af->tmp_path, sizeof af->tmp_path, "%s.tmp.%ld.dermis", path, (long)getpid());
    int slot = cleanup_take(af->tmp_path, 3);
    int fd = -1;
    for (int k = 0; fd < 0 && k < 100; ++k) {
        if (k > 0) {
            snprintf(af->tmp_path, sizeof af->tmp_path, "%s.tmp.%ld-%d.dermis", path, (long)getpid(), k);
            if (slot >= 0) memcpy(g_cleanup_path[slot], af->tmp_path, strlen(af->tmp_path) + 1);
        }
        fd = open(af->tmp_path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST) break;
    }
    int e = errno;
    if (fd >= 0) {
        char mark[512];
        tmp_marker((long)getpid(), mark, sizeof mark);
        (void)fsetxattr(fd, TMP_XATTR, mark, strlen(mark), 0); /* unsupported: no proof, never removed by others */
        close(fd);
    }
    af->cleanup_slot = fd >= 0 ? slot : -1;
    if (slot >= 0) atomic_store(&g_cleanup_state[slot], fd >= 0 ? 1 : 0);
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (fd < 0) {
        af->tmp_path[0] = '\0';
        return dm_fail(err, DM_ERR_FILE_WRITE, "%s: cannot write in the folder '%s' (%s)", path, dir,
                       e == EEXIST ? "no free temporary name" : strerror(e));
    }
    return DM_OK;
}

dm_result dm_atomic_open(dm_atomic_file *af, const char *path, dm_error *err)
{
    dm_result r = dm_atomic_begin(af, path, err);
    if (r != DM_OK) return r;
    af->fp = fopen(af->tmp_path, "wb");
    if (!af->fp) {
        int e = errno;
        dm_atomic_abort(af);
        return dm_fail(err, DM_ERR_FILE_WRITE, "%s: cannot write (%s)", path, strerror(e));
    }
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
