/* libFuzzer target: the glTF reader (dm_mesh_load on .glb / .gltf) on arbitrary bytes,
 * in this process (in_process = 1) so that the sanitizers see every read of the
 * adapter's own checks (accessor ranges, index ranges, transforms, welding). Input that
 * starts with "glTF" is written as a .glb, anything else as a .gltf, in a private
 * folder (external URIs resolve there and find nothing). Every failure must explain
 * itself; every success must be a valid mesh. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mesh/dm_mesh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char folder[256], glb[300], gltf[300];

static void cleanup(void)
{
    unlink(glb);
    unlink(gltf);
    rmdir(folder);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!folder[0]) {
        const char *t = getenv("TMPDIR");
        snprintf(folder, sizeof folder, "%s/dermis-fuzz-gltf-XXXXXX", t && *t ? t : "/tmp");
        if (!mkdtemp(folder)) abort();
        snprintf(glb, sizeof glb, "%s/in.glb", folder);
        snprintf(gltf, sizeof gltf, "%s/in.gltf", folder);
        atexit(cleanup);
    }
    const char *path = size >= 4 && !memcmp(data, "glTF", 4) ? glb : gltf;
    FILE *f = fopen(path, "wb");
    if (!f) abort();
    if (size && fwrite(data, 1, size, f) != size) abort();
    fclose(f);
    dm_mesh_load_options o = {.in_process = 1, .mesh_name = size > 0 && (data[size - 1] & 1) ? "a" : NULL};
    dm_mesh m;
    dm_error err = {0};
    if (dm_mesh_load(path, &o, &m, &err) == DM_OK) {
        if (dm_mesh_validate(&m, path, &err) != DM_OK) abort();
    } else if (!err.detail[0] || m.positions) {
        abort(); /* every failure explains itself and leaves nothing allocated */
    }
    dm_mesh_free(&m);
    return 0;
}
