/* tmpdir.h — a fresh temporary folder per test, and running a tool with its exit code. */
#ifndef TEST_TMPDIR_H
#define TEST_TMPDIR_H

#include <dirent.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

/* A fresh folder under $DERMIS_TEST_TMP (scripts/run-tests.sh makes one per run and
 * removes it when every test passed), else under /tmp. */
static inline const char *test_tmpdir(char *buf, size_t size)
{
    const char *root = getenv("DERMIS_TEST_TMP");
    snprintf(buf, size, "%s/dermis-test-XXXXXX", root && *root ? root : "/tmp");
    return mkdtemp(buf);
}

static inline char *test_slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    size_t got = fread(s, 1, (size_t)n, f);
    s[got] = 0;
    fclose(f);
    return s;
}

/* Runs a shell command line, stdout/stderr to log (may be NULL: discarded); returns the
 * exit code, or -1 if it did not exit normally. A viewer that could not connect to the test's
 * X server (xvfb-run's; once in a sanitizer run a connection was refused while the other
 * twelve viewer tests of that binary connected) is run again, twice at most, a second
 * apart, and says so on stderr: the display, not the viewer, failed there. */
static inline int test_run(const char *cmd, const char *log)
{
    char line[12288];
    int n = snprintf(line, sizeof line, "%s >%s 2>&1", cmd, log ? log : "/dev/null");
    if (n < 0 || (size_t)n >= sizeof line) return -1; /* too long to run as given */
    for (int attempt = 0;; ++attempt) {
        int st = system(line);
        int rc = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
        if (rc != 3 || !log || attempt == 2) return rc;
        char *out = test_slurp(log);
        bool display = out && strstr(out, "Failed to open display");
        free(out);
        if (!display) return rc;
        fprintf(stderr, "note: the X server refused a connection; running again: %.200s\n", cmd);
        sleep(1);
    }
}

/* Number of entries of a folder whose name contains `part` (NULL: all). */
static inline int test_count_files(const char *dir, const char *part)
{
    DIR *d = opendir(dir);
    if (!d) return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (e->d_name[0] != '.' && (!part || strstr(e->d_name, part))) ++n;
    closedir(d);
    return n;
}

#endif
