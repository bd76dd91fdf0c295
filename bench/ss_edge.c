/* ss_edge.c — the screen-space technique at an albedo edge against the profile's (issue #29):
 * bench/results/ss_edge.md, the section bench/accuracy.c also writes into accuracy.md, in
 * seconds instead of that bench's hour. Usage: ss_edge [OUTDIR] (default bench/results). */
#include "common/bench_util.h"
#include "common/edge_table.h"
#include "host/dm_osmesa.h"

int main(int argc, char **argv)
{
    const char *outdir = argc > 1 ? argv[1] : "bench/results";
    dm_osmesa *ctx = NULL;
    dm_error err = {0};
    if (dm_osmesa_create(&ctx, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        return 3;
    }
    FILE *md = bench_open(outdir, "ss_edge.md", "Screen-space SSS at an albedo edge");
    int rc = md ? edge_table(md) : -1;
    if (md) fclose(md);
    dm_osmesa_destroy(ctx);
    if (rc == 0) printf("ss edge bench: wrote %s/ss_edge.md\n", outdir);
    return rc == 0 ? 0 : 3;
}
