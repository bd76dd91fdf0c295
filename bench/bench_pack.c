/* bench_pack — pack time per bundled scene (the dermis-pack tool end to end, median of 5
 * runs), pack sizes, and open-and-verify time of dm_pack_open (median of 21 runs, file in
 * the page cache). Writes pack.md into the folder given. Aims (issue 6): the full head
 * pack in under 3 s, open and verify in under 50 ms. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/utsname.h>
#include <unistd.h>

#include "core/dm_cli.h"
#include "core/dm_file.h"
#include "pack/dm_pack.h"
#include "core/dm_parallel.h"
#include "core/dm_sort.h"

enum { PACK_RUNS = 5, OPEN_RUNS = 21, MAX_SCENES = 16 };

static double median(double *v, int n)
{
    dm_sort_doubles(v, (size_t)n);
    return v[n / 2];
}

static void cpu_model(char *out, size_t n)
{
    snprintf(out, n, "unknown");
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (!f) return;
    char line[512];
    while (fgets(line, sizeof line, f))
        if (strncmp(line, "model name", 10) == 0) {
            char *c = strchr(line, ':');
            if (c) {
                snprintf(out, n, "%s", c + 2);
                out[strcspn(out, "\n")] = '\0';
            }
            break;
        }
    fclose(f);
}

static int by_name(const void *a, const void *b)
{
    return strcmp((const char *)a, (const char *)b);
}

int main(int argc, char **argv)
{
    const char *outdir = argc > 1 ? argv[1] : "bench/results";
    char bindir[1024], tool[1200];
    dm_dirname(argv[0], bindir, sizeof bindir);
    snprintf(tool, sizeof tool, "%s/../bin/dermis-pack", bindir);
    if (access(tool, X_OK) != 0) {
        fprintf(stderr, "error: %s: not found, expected dermis-pack beside the bench (make tools)\n", tool);
        return 1;
    }
    char scenes[MAX_SCENES][256];
    int ns = 0;
    DIR *d = opendir("assets/scenes");
    if (!d) {
        fprintf(stderr, "error: assets/scenes: cannot open (run from the repository root)\n");
        return 1;
    }
    for (struct dirent *e; (e = readdir(d)) && ns < MAX_SCENES;)
        if (strstr(e->d_name, ".json")) snprintf(scenes[ns++], sizeof scenes[0], "%s", e->d_name);
    closedir(d);
    qsort(scenes, (size_t)ns, sizeof scenes[0], by_name);

    char path[1400];
    snprintf(path, sizeof path, "%s/pack.md", outdir);
    FILE *md = fopen(path, "w");
    if (!md) {
        fprintf(stderr, "error: %s: cannot write\n", path);
        return 1;
    }
    struct utsname u;
    uname(&u);
    char cpu[256];
    cpu_model(cpu, sizeof cpu);
    fprintf(md, "# dermis-pack and the pack reader\n\n");
    fprintf(md, "Machine: `%s %s %s %s %s`, %s, %d cores.\n\n", u.sysname, u.nodename, u.release, u.version,
            u.machine, cpu, dm_cpu_count());
    fprintf(md, "Pack time: `dermis-pack SCENE -o FILE --quiet` end to end (process start, image decoding, "
                "LUT bakes, write with fsync, verify), median of %d runs. Open+verify: `dm_pack_open` "
                "(map, header, manifest schema, bounds, every checksum, finiteness, required entries) "
                "then `dm_pack_close`, median of %d runs with the file in the page cache.\n\n",
            PACK_RUNS, OPEN_RUNS);
    fprintf(md, "Every entry each scene's effects need: the split mesh, maps, LUTs, profile, the stretch "
                "chain at the scene's irradiance size (RG32F, one layer per Gaussian) and the environment "
                "(SH, RGBA32F specular levels and background).\n\n");
    fprintf(md, "| scene | entries | pack size (MiB) | pack time (ms, median) | open+verify (ms, median) | aim |\n");
    fprintf(md, "|---|---:|---:|---:|---:|---|\n");
    mkdir("build", 0755);
    mkdir("build/bench", 0755);
    for (int s = 0; s < ns; ++s) {
        char out[600], cmd[3000];
        snprintf(out, sizeof out, "build/bench/%.*s.dpk", (int)(strlen(scenes[s]) - 5), scenes[s]);
        snprintf(cmd, sizeof cmd, "%s assets/scenes/%s -o %s --quiet", tool, scenes[s], out);
        double t[PACK_RUNS], o[OPEN_RUNS];
        int bad = 0;
        for (int r = 0; r < PACK_RUNS; ++r) {
            double t0 = dm_now_ms();
            int rc = system(cmd);
            t[r] = dm_now_ms() - t0;
            if (rc != 0) bad = 1;
        }
        if (bad) {
            fprintf(stderr, "error: %s failed\n", cmd);
            fprintf(md, "| %s | failed | | | | |\n", scenes[s]);
            continue;
        }
        dm_pack pack;
        dm_error err = {0};
        int entries = 0;
        size_t size = 0;
        for (int r = 0; r < OPEN_RUNS; ++r) {
            double t0 = dm_now_ms();
            dm_result res = dm_pack_open(out, &pack, &err);
            o[r] = dm_now_ms() - t0;
            if (res != DM_OK) {
                fprintf(stderr, "error: %s\n", err.detail);
                fclose(md);
                return 1;
            }
            entries = pack.entry_count;
            size = pack.size;
            dm_pack_close(&pack);
        }
        double tp = median(t, PACK_RUNS), to = median(o, OPEN_RUNS);
        fprintf(md, "| %s | %d | %.2f | %.0f | %.2f | %s |\n", scenes[s], entries, size / 1048576.0, tp, to,
                tp < 3000.0 && to < 50.0 ? "met (< 3 s, < 50 ms)" : "MISSED");
        fprintf(stderr, "   %-20s %2d entries %7.2f MiB  pack %6.0f ms  open+verify %6.2f ms\n", scenes[s], entries,
                size / 1048576.0, tp, to);
    }
    fclose(md);
    fprintf(stderr, "   wrote %s\n", path);
    return 0;
}
