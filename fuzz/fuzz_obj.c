/* libFuzzer target: the OBJ reader (dm_mesh_load on .obj: dm_mesh_check_file's checks,
 * then OpenMesh's reader through the adapter) on arbitrary bytes, in this process
 * (in_process = 1) so that the sanitizers and the coverage see both. The input is
 * written as a .obj in a private folder (a mtllib resolves there and finds nothing).
 * The last byte, when odd, asks for computed normals. Every failure must explain
 * itself; every success must be a valid mesh. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mesh/dm_mesh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char folder[256], obj[300];

static void cleanup(void)
{
    unlink(obj);
    rmdir(folder);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!folder[0]) {
        const char *t = getenv("TMPDIR");
        snprintf(folder, sizeof folder, "%s/dermis-fuzz-obj-XXXXXX", t && *t ? t : "/tmp");
        if (!mkdtemp(folder)) abort();
        snprintf(obj, sizeof obj, "%s/in.obj", folder);
        atexit(cleanup);
    }
    FILE *f = fopen(obj, "wb");
    if (!f) abort();
    if (size && fwrite(data, 1, size, f) != size) abort();
    fclose(f);
    dm_mesh_load_options o = {.in_process = 1, .uvs_optional = size > 0 && (data[0] & 1),
                              .ignore_file_normals = size > 0 && (data[size - 1] & 1)};
    dm_mesh m;
    dm_error err = {0};
    if (dm_mesh_load(obj, &o, &m, &err) == DM_OK) {
        if (dm_mesh_validate(&m, obj, &err) != DM_OK) abort();
    } else if (!err.detail[0] || m.positions) {
        abort(); /* every failure explains itself and leaves nothing allocated */
    }
    dm_mesh_free(&m);
    return 0;
}
