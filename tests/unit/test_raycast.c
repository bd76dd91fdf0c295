/* dm_raycast against closed forms: a UV sphere of radius R = 20 mm (10 units × 2 mm/unit).
 * The mesh is inscribed (vertices on the sphere), so a hit along a ray towards the centre
 * lies between R·cos(δ) and R from the centre, δ the largest angle from a face's centre to
 * its corners (< π/32 for 64 × 32 cells): the tolerance below is that sagitta, R(1 − cos δ)
 * ≈ 0.1 mm, not a fudge. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/dm_raycast.h"

#define PI 3.14159265358979323846
enum { NU = 64, NV = 32 };
static const double R_MM = 20.0, MM_PER_UNIT = 2.0;

/* A closed UV sphere of radius 10 units centred at the origin, counter-clockwise outside. */
static void sphere(dm_mesh *m)
{
    dm_error err = {0};
    cr_assert_eq(dm_mesh_alloc((NU + 1) * (NV + 1), 2 * NU * NV, m, &err), DM_OK);
    for (int j = 0; j <= NV; ++j)
        for (int i = 0; i <= NU; ++i) {
            double th = PI * j / NV, ph = 2 * PI * i / NU;
            float *p = m->positions + (j * (NU + 1) + i) * 3;
            p[0] = (float)(10.0 * sin(th) * cos(ph));
            p[1] = (float)(10.0 * cos(th));
            p[2] = (float)(-10.0 * sin(th) * sin(ph));
        }
    int t = 0;
    for (int j = 0; j < NV; ++j)
        for (int i = 0; i < NU; ++i) {
            uint32_t a = j * (NU + 1) + i, b = a + 1, c = a + NU + 1, d = c + 1;
            /* (i, j) → (θ down from +Y, φ): counter-clockwise seen from outside is a, c, d */
            const uint32_t tri[2][3] = {{a, c, d}, {a, d, b}};
            for (int h = 0; h < 2; ++h, ++t)
                for (int k = 0; k < 3; ++k) {
                    m->indices[t * 3 + k] = tri[h][k];
                    m->uvs[(t * 3 + k) * 2] = 0.5f;
                    m->uvs[(t * 3 + k) * 2 + 1] = 0.5f;
                }
        }
    dm_mesh_compute_normals(m);
    cr_assert_eq(dm_mesh_validate(m, "sphere", &err), DM_OK, "%s", err.detail);
}

static dm_raycast *make(dm_mesh *m)
{
    sphere(m);
    dm_raycast *rc = NULL;
    dm_error err = {0};
    cr_assert_eq(dm_raycast_create(m, MM_PER_UNIT, &rc, &err), DM_OK, "%s", err.detail);
    return rc;
}

static double sagitta(void)
{
    return R_MM * (1 - cos(PI / NV)) + 1e-4;
}

Test(raycast, front_faces_are_outside)
{
    dm_mesh m;
    dm_raycast *rc = make(&m);
    const double org[3] = {0, 0, 100}, dir[3] = {0, 0, -1};
    dm_ray_hit h;
    cr_assert(dm_raycast_closest(rc, org, dir, 0, INFINITY, true, &h));
    cr_assert_gt(h.ng[2], 0.99, "the hit facing the ray must be a front face, ng.z = %g", h.ng[2]);
    dm_raycast_destroy(rc);
    dm_mesh_free(&m);
}

Test(raycast, rays_towards_the_centre)
{
    dm_mesh m;
    dm_raycast *rc = make(&m);
    srand(7);
    for (int k = 0; k < 500; ++k) {
        double d[3], l2 = 0;
        do {
            l2 = 0;
            for (int c = 0; c < 3; ++c) d[c] = 2.0 * rand() / RAND_MAX - 1, l2 += d[c] * d[c];
        } while (l2 < 0.01 || l2 > 1);
        double org[3], dir[3];
        for (int c = 0; c < 3; ++c) {
            d[c] /= sqrt(l2);
            org[c] = 100 * d[c];
            dir[c] = -d[c] * 3.0; /* not unit: t is in units of |dir| */
        }
        dm_ray_hit h;
        cr_assert(dm_raycast_closest(rc, org, dir, 0, INFINITY, true, &h), "ray %d missed", k);
        double dist = 3.0 * h.t; /* mm travelled */
        cr_assert(dist >= 100 - R_MM - 1e-3 && dist <= 100 - R_MM + sagitta(), "ray %d: %g mm, expected %g..%g", k,
                  dist, 100 - R_MM, 100 - R_MM + sagitta());
        /* the barycentrics give the same point */
        double p[3] = {0};
        const double w[3] = {1.0 - h.b1 - h.b2, h.b1, h.b2};
        for (int c3 = 0; c3 < 3; ++c3)
            for (int c = 0; c < 3; ++c)
                p[c] += w[c3] * m.positions[m.indices[h.triangle * 3 + c3] * 3 + c] * MM_PER_UNIT;
        for (int c = 0; c < 3; ++c) cr_assert_lt(fabs(p[c] - (org[c] + h.t * dir[c])), 1e-3);
    }
    dm_raycast_destroy(rc);
    dm_mesh_free(&m);
}

/* Parallel rays on a grid: hit iff r < R (rays within the sagitta band of the rim are not
 * judged), at depth 100 − √(R² − r²). */
Test(raycast, parallel_rays_silhouette)
{
    dm_mesh m;
    dm_raycast *rc = make(&m);
    int hits = 0;
    for (int y = -30; y <= 30; ++y)
        for (int x = -30; x <= 30; ++x) {
            double ox = x * 0.75, oy = y * 0.75, r = sqrt(ox * ox + oy * oy);
            const double org[3] = {ox, oy, 100}, dir[3] = {0, 0, -1};
            dm_ray_hit h;
            bool hit = dm_raycast_closest(rc, org, dir, 0, INFINITY, true, &h);
            if (fabs(r - R_MM) < 0.5) continue;
            cr_assert_eq(hit, r < R_MM, "ray at r = %g mm: hit %d", r, hit);
            if (!hit) continue;
            ++hits;
            double expect = 100 - sqrt(R_MM * R_MM - r * r);
            cr_assert(h.t >= expect - 1e-3 && h.t <= expect + 1.0, "r = %g: t = %g, expected %g", r, h.t, expect);
        }
    cr_assert_gt(hits, 2000);
    dm_raycast_destroy(rc);
    dm_mesh_free(&m);
}

Test(raycast, occlusion_segments_and_culling)
{
    dm_mesh m;
    dm_raycast *rc = make(&m);
    const double org[3] = {0, 0, 100}, dir[3] = {0, 0, -1}, centre[3] = {0, 0, 0}, up[3] = {0, 1, 0};
    cr_assert_not(dm_raycast_occluded(rc, org, dir, 0, 70), "the segment ends before the sphere");
    cr_assert(dm_raycast_occluded(rc, org, dir, 0, 90), "the segment enters the sphere");
    cr_assert_not(dm_raycast_occluded(rc, org, dir, 130, 200), "the segment starts beyond it");
    const double side[3] = {R_MM + 0.5, 0, 100};
    cr_assert_not(dm_raycast_occluded(rc, side, dir, 0, INFINITY), "passes beside the sphere");
    /* from the centre every face is seen from behind: occlusion sees it, culled rays do not */
    cr_assert(dm_raycast_occluded(rc, centre, up, 0, INFINITY));
    dm_ray_hit h;
    cr_assert_not(dm_raycast_closest(rc, centre, up, 0, INFINITY, true, &h));
    cr_assert_eq(h.triangle, -1);
    cr_assert(dm_raycast_closest(rc, centre, up, 0, INFINITY, false, &h));
    cr_assert(h.t >= R_MM - sagitta() && h.t <= R_MM + 1e-3, "t = %g", h.t);
    cr_assert_gt(h.ng[1], 0.99, "seen from inside, the front normal points along the ray: %g", h.ng[1]);
    dm_raycast_destroy(rc);
    dm_mesh_free(&m);
}

Test(raycast, epsilon_and_bounds)
{
    dm_mesh m;
    dm_raycast *rc = make(&m);
    double e = dm_raycast_epsilon_mm(rc), c[3], r;
    cr_assert(e > 0 && e < 1e-3 * R_MM, "epsilon %g mm", e);
    dm_raycast_bounds(rc, c, &r);
    cr_assert_lt(fabs(r - R_MM), 1e-4);
    for (int k = 0; k < 3; ++k) cr_assert_lt(fabs(c[k]), 1e-4);
    dm_raycast_destroy(rc);
    dm_mesh_free(&m);
}

/* Two ray casters built from the same mesh answer every ray bit for bit alike. */
Test(raycast, deterministic)
{
    dm_mesh m, m2;
    dm_raycast *a = make(&m), *b = make(&m2);
    srand(11);
    for (int k = 0; k < 2000; ++k) {
        double org[3], dir[3];
        for (int c = 0; c < 3; ++c) {
            org[c] = 60.0 * rand() / RAND_MAX - 30;
            dir[c] = 2.0 * rand() / RAND_MAX - 1;
        }
        dm_ray_hit ha, hb;
        bool x = dm_raycast_closest(a, org, dir, 0, INFINITY, false, &ha);
        bool y = dm_raycast_closest(b, org, dir, 0, INFINITY, false, &hb);
        cr_assert_eq(x, y);
        cr_assert_eq(memcmp(&ha, &hb, sizeof ha), 0, "ray %d answered differently", k);
        cr_assert_eq(dm_raycast_occluded(a, org, dir, 0, 10), dm_raycast_occluded(b, org, dir, 0, 10));
    }
    dm_raycast_destroy(a);
    dm_raycast_destroy(b);
    dm_mesh_free(&m);
    dm_mesh_free(&m2);
}

Test(raycast, bad_scale)
{
    dm_mesh m;
    sphere(&m);
    dm_raycast *rc = NULL;
    dm_error err = {0};
    cr_assert_eq(dm_raycast_create(&m, 0.0, &rc, &err), DM_ERR_RANGE);
    cr_assert_eq(dm_raycast_create(&m, NAN, &rc, &err), DM_ERR_RANGE);
    cr_assert_null(rc);
    dm_mesh_free(&m);
}
