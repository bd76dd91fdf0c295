/* dm_isolate.c — a reader in a forked child, its reply through a pipe (dm_isolate.h).
 * Moved here from the OpenMesh adapter so that every reader that trusts its input
 * (OpenMesh, tinygltf) shares one mechanism. */
#include "mesh/dm_isolate.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/dm_cli.h"

double dm_isolate_limit_ms(const char *path)
{
    struct stat sb;
    double size_mb = stat(path, &sb) == 0 ? (double)sb.st_size / 1e6 : 0.0;
    return 30000.0 + 1000.0 * size_mb;
}

int dm_isolate_write(int fd, const void *data, size_t size)
{
    const char *p = data;
    while (size > 0) {
        ssize_t n = write(fd, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return 0;
        p += n, size -= (size_t)n;
    }
    return 1;
}

int dm_isolate_read(dm_isolate_pipe *pp, void *data, size_t size)
{
    char *p = data;
    while (size > 0) {
        double left = pp->deadline_ms - dm_now_ms();
        if (left <= 0) return pp->timed_out = 1, pp->lost = 1, 0;
        struct pollfd pfd = {pp->fd, POLLIN, 0};
        int pr = poll(&pfd, 1, left > 1e6 ? 1000000 : (int)left + 1);
        if (pr < 0 && errno == EINTR) continue;
        if (pr < 0) return pp->lost = 1, 0;
        if (pr == 0) continue;
        ssize_t n = read(pp->fd, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return pp->lost = 1, 0;
        p += n, size -= (size_t)n;
    }
    return 1;
}

typedef struct result_wire {
    int32_t result;
    char detail[sizeof(((dm_error *)0)->detail)];
} result_wire;

int dm_isolate_write_result(int fd, dm_result r, const dm_error *e)
{
    result_wire w;
    memset(&w, 0, sizeof w);
    w.result = (int32_t)r;
    if (r != DM_OK && e) memcpy(w.detail, e->detail, sizeof w.detail);
    return dm_isolate_write(fd, &w, sizeof w);
}

int dm_isolate_read_result(dm_isolate_pipe *pp, dm_result *r, dm_error *err)
{
    result_wire w;
    if (!dm_isolate_read(pp, &w, sizeof w)) return 0;
    w.detail[sizeof w.detail - 1] = '\0';
    *r = (dm_result)w.result;
    if (*r != DM_OK) dm_fail(err, *r, "%s", w.detail);
    return 1;
}

dm_result dm_isolate_run(const char *path, double limit_ms, dm_isolate_child_fn child, dm_isolate_parent_fn parent,
                         void *ctx, dm_error *err)
{
    int fds[2];
    if (pipe(fds) != 0) return dm_fail(err, DM_ERR_INTERNAL, "%s: pipe failed (%s)", path, strerror(errno));
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]), close(fds[1]);
        return dm_fail(err, DM_ERR_INTERNAL, "%s: fork failed (%s)", path, strerror(errno));
    }
    if (pid == 0) { /* child: readers may print (OpenMesh writes to std::cerr directly) */
        close(fds[0]);
        int devnull = open("/dev/null", O_WRONLY);
        if (devnull >= 0) dup2(devnull, 1), dup2(devnull, 2);
        child(ctx, fds[1]);
        _exit(0);
    }
    close(fds[1]);
    dm_isolate_pipe pp = {fds[0], dm_now_ms() + limit_ms, 0, 0};
    dm_result r = parent(ctx, &pp, err);
    close(fds[0]);
    if (pp.timed_out) kill(pid, SIGKILL);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!pp.lost) return r;
    if (pp.timed_out)
        return dm_fail(err, DM_ERR_FORMAT, "%s: the reader did not finish in %.0f s (a malformed file), expected a mesh",
                       path, limit_ms / 1000.0);
    if (WIFSIGNALED(status))
        return dm_fail(err, DM_ERR_FORMAT, "%s: the reader crashed on this file (signal %d): malformed, expected a mesh",
                       path, WTERMSIG(status));
    return dm_fail(err, DM_ERR_FORMAT, "%s: the reader stopped early (exit status %d): malformed, expected a mesh", path,
                   WIFEXITED(status) ? WEXITSTATUS(status) : -1);
}
