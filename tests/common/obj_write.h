/* obj_write.h — a test mesh written as Wavefront OBJ (positions, one vt per triangle corner),
 * for tests that pack their own geometry with dermis-pack. */
#ifndef TEST_OBJ_WRITE_H
#define TEST_OBJ_WRITE_H

#include <criterion/criterion.h>
#include <stdio.h>

#include "mesh/dm_mesh.h"

static inline void test_write_obj(const char *path, const dm_mesh *m)
{
    FILE *f = fopen(path, "w");
    cr_assert(f, "cannot write %s", path);
    for (int v = 0; v < m->vertex_count; ++v)
        fprintf(f, "v %.9g %.9g %.9g\n", m->positions[3 * v], m->positions[3 * v + 1], m->positions[3 * v + 2]);
    for (int c = 0; c < 3 * m->triangle_count; ++c) fprintf(f, "vt %.9g %.9g\n", m->uvs[2 * c], m->uvs[2 * c + 1]);
    for (int t = 0; t < m->triangle_count; ++t)
        fprintf(f, "f %u/%d %u/%d %u/%d\n", m->indices[3 * t] + 1, 3 * t + 1, m->indices[3 * t + 1] + 1, 3 * t + 2,
                m->indices[3 * t + 2] + 1, 3 * t + 3);
    fclose(f);
}

#endif
