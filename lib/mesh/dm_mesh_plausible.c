#include "mesh/dm_mesh_plausible.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>

double dm_mesh_signed_volume(const dm_mesh *m)
{
    assert(m);
    double c[3] = {0, 0, 0};
    for (int32_t v = 0; v < m->vertex_count; ++v)
        for (int k = 0; k < 3; ++k) c[k] += m->positions[3 * v + k];
    for (int k = 0; k < 3; ++k) c[k] /= m->vertex_count > 0 ? m->vertex_count : 1;
    double vol = 0.0;
    for (int32_t t = 0; t < m->triangle_count; ++t) {
        double p[3][3];
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) p[i][k] = m->positions[3 * m->indices[3 * t + i] + k] - c[k];
        vol += p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) - p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
               p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
    }
    return vol / 6.0;
}

double dm_mesh_extent(const dm_mesh *m)
{
    assert(m);
    if (m->vertex_count <= 0) return 0.0;
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) lo[k] = hi[k] = m->positions[k];
    for (int32_t v = 1; v < m->vertex_count; ++v)
        for (int k = 0; k < 3; ++k) {
            double x = m->positions[3 * v + k];
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    double e = 0.0;
    for (int k = 0; k < 3; ++k) e = hi[k] - lo[k] > e ? hi[k] - lo[k] : e;
    return e;
}

int dm_mesh_plausible(const dm_mesh *m, double mm_per_unit, const char *what, char *msg, size_t msg_size)
{
    assert(m && what && msg && msg_size > 0);
    msg[0] = '\0';
    int count = 0;
    size_t n = 0;
    double vol = dm_mesh_signed_volume(m), extent = dm_mesh_extent(m);
    if (vol < 0.0) {
        n += (size_t)snprintf(msg + n, msg_size - n,
                              "warning: %s: the faces wind inward (signed volume %.4g units^3 < 0: normals point into "
                              "the mesh), so light would shade the inside: flip the faces' winding in the mesh file\n",
                              what, vol);
        ++count;
    }
    double mm = extent * mm_per_unit;
    if (n < msg_size && extent > 0.0 && (mm < DM_MESH_PLAUSIBLE_MIN_MM || mm > DM_MESH_PLAUSIBLE_MAX_MM)) {
        snprintf(msg + n, msg_size - n,
                 "warning: %s: at mm_per_unit %g the mesh spans %.4g mm (its bounding box's largest side, %.4g units); "
                 "a head spans about 200-450 mm, so the diffusion (in mm) would look %s: set mm_per_unit to about %.3g\n",
                 what, mm_per_unit, mm, extent, mm < DM_MESH_PLAUSIBLE_MIN_MM ? "like wax" : "like hard plastic",
                 300.0 / extent);
        ++count;
    }
    return count;
}
