/* The ground truth's own error bars (dm_reference.h): closed forms on a plane (constant,
 * cosine), a sphere (linear irradiance, chord distances), a delta (mass, centroid, second
 * moment), convergence against a finer quadrature, thread and split invariance, and the
 * hard cases (degenerate triangles, one triangle, no surface, extreme mm_per_unit). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "../common/grid_mesh.h"
#include "reference/dm_reference.h"
#include "core/dm_math.h"

/* ---- fixtures ---------------------------------------------------------------------- */

#define PLANE_MM 64.0
static void plane_pos(double s, double t, double o[3]) { o[0] = PLANE_MM * s, o[1] = PLANE_MM * t, o[2] = 0; }
static void uv_id(double s, double t, double o[3]) { o[0] = s, o[1] = t, o[2] = 0; }

#define SPHERE_MM 20.0
static void sphere_pos(double s, double t, double o[3])
{
    double phi = DM_2PI * s, theta = DM_PI * t; /* theta from the south pole */
    o[0] = SPHERE_MM * sin(theta) * cos(phi), o[1] = SPHERE_MM * sin(theta) * sin(phi);
    o[2] = -SPHERE_MM * cos(theta);
}

typedef double (*field_fn)(double u, double v);

/* An N×N atlas, every texel covered, I(u, v) at texel centres, grey. */
static float *atlas_from(int n, field_fn f)
{
    float *a = malloc(sizeof *a * 4 * (size_t)n * n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            float v = (float)f((i + 0.5) / n, (j + 0.5) / n);
            float *t = a + 4 * ((size_t)j * n + i);
            t[0] = t[1] = t[2] = v;
            t[3] = 1.0f;
        }
    return a;
}

static void gems3_kernel(dm_reference_kernel *k)
{
    dm_profile p;
    dm_profile_gems3_skin(&p);
    dm_error err = {0};
    cr_assert_eq(dm_reference_kernel_from_profile(&p, k, &err), DM_OK, "%s", err.detail);
}

/* The target at plane point (x, y) mm of the grid mesh (nu cells a side). */
static dm_reference_target plane_target(int nu, double x, double y)
{
    double s = x / PLANE_MM * nu, t = y / PLANE_MM * nu;
    int i = (int)floor(s), j = (int)floor(t);
    double fs = s - i, ft = t - j;
    dm_reference_target tg;
    /* cell (i, j): triangle 0 = (0,0) (1,0) (1,1); triangle 1 = (0,0) (1,1) (0,1) */
    if (fs >= ft) tg = (dm_reference_target){2 * (j * nu + i), (float)(fs - ft), (float)ft};
    else tg = (dm_reference_target){2 * (j * nu + i) + 1, (float)fs, (float)(ft - fs)};
    return tg;
}

static dm_reference *make_ref(const dm_mesh *m, double mm_per_unit, int n, const float *rgba,
                              const dm_reference_kernel *k, const dm_reference_options *o)
{
    dm_reference *ref = NULL;
    dm_error err = {0};
    dm_reference_atlas atlas = {n, n, rgba};
    cr_assert_eq(dm_reference_create(m, mm_per_unit, &atlas, k, o, &ref, &err), DM_OK, "%s", err.detail);
    return ref;
}

static void eval(const dm_reference *ref, const dm_reference_target *t, size_t n, float *rgb, float *levels)
{
    dm_error err = {0};
    cr_assert_eq(dm_reference_eval(ref, t, n, rgb, levels, &err), DM_OK, "%s", err.detail);
}

/* ---- plane ------------------------------------------------------------------------- */

static double one(double u, double v) { (void)u, (void)v; return 1.0; }
#define COS_PERIOD_MM 16.0
static double cosine(double u, double v) { (void)v; return 1.0 + 0.5 * cos(DM_2PI * u * PLANE_MM / COS_PERIOD_MM); }

/* Interior points (≥ 4σ of the widest Gaussian, 10.9 mm, from every edge) of a 64 mm plane,
 * each Gaussian on its own: constant irradiance gives 1 (the cut's dropped mass restored),
 * to 1e-4 (the quadrature's residue, O((h/σ)⁴) at h = 0.3σ). */
Test(reference, plane_constant)
{
    dm_mesh m;
    grid_mesh(16, 16, plane_pos, uv_id, &m);
    float *a = atlas_from(256, one);
    dm_reference_kernel k;
    gems3_kernel(&k);
    dm_reference *ref = make_ref(&m, 1.0, 256, a, &k, NULL);
    dm_reference_stats st;
    dm_reference_get_stats(ref, &st);
    cr_expect(st.narrow_gaussians > 0 && st.wide_gaussians > 0, "both paths: %d narrow, %d wide", st.narrow_gaussians,
              st.wide_gaussians);
    cr_expect(fabs(st.surface_area_mm2 - PLANE_MM * PLANE_MM) < 1e-6);
    enum { N = 9 };
    dm_reference_target t[N];
    for (int i = 0; i < N; ++i) t[i] = plane_target(16, 12.3 + 4.9 * i, 31.7 - 1.3 * i);
    float rgb[N * 3], lv[N * 6 * 3];
    eval(ref, t, N, rgb, lv);
    for (int i = 0; i < N; ++i) {
        for (int kk = 0; kk < 6; ++kk) cr_expect(fabs(lv[(i * 6 + kk) * 3] - 1.0) < 1e-4, "S%d = %.7f", kk, lv[(i * 6 + kk) * 3]);
        cr_expect(fabs(rgb[3 * i] - 1.0) < 1e-4, "D = %.7f", rgb[3 * i]);
    }
    dm_reference_destroy(ref);
    free(a);
    dm_mesh_free(&m);
}

/* I = 1 + ½cos(2πx/λ), λ = 16 mm: S_k = 1 + ½cos(2πx/λ)·exp(−2π²v_k/λ²). The atlas holds I
 * at texel centres (0.25 mm) and is read bilinearly: that interpolant differs from I by at
 * most h²/8·|I''| = 0.25²/8·½(2π/16)² = 6.0e-4; the tolerance is that plus 1e-4. */
Test(reference, plane_cosine)
{
    dm_mesh m;
    grid_mesh(16, 16, plane_pos, uv_id, &m);
    float *a = atlas_from(256, cosine);
    dm_reference_kernel k;
    gems3_kernel(&k);
    dm_reference *ref = make_ref(&m, 1.0, 256, a, &k, NULL);
    enum { N = 16 };
    dm_reference_target t[N];
    double x[N];
    for (int i = 0; i < N; ++i) {
        x[i] = 12.0 + 2.5 * i + 0.37;
        t[i] = plane_target(16, x[i], 30.2);
    }
    float rgb[N * 3], lv[N * 6 * 3];
    eval(ref, t, N, rgb, lv);
    double worst = 0.0;
    for (int i = 0; i < N; ++i)
        for (int kk = 0; kk < 6; ++kk) {
            double want = 1.0 + 0.5 * cos(DM_2PI * x[i] / COS_PERIOD_MM) *
                                    exp(-2.0 * DM_PI * DM_PI * k.variance_mm2[kk] / (COS_PERIOD_MM * COS_PERIOD_MM));
            double e = fabs(lv[(i * 6 + kk) * 3] - want);
            worst = fmax(worst, e);
            cr_expect(e < 7e-4, "x %.2f S%d %.6f want %.6f", x[i], kk, lv[(i * 6 + kk) * 3], want);
        }
    cr_log_info("plane cosine: worst |S - closed form| = %.2e", worst);
    dm_reference_destroy(ref);
    free(a);
    dm_mesh_free(&m);
}

/* A delta: one texel lit, the sharpest input an atlas can hold. Its bilinear interpolant is a
 * tent of mass h² (h the texel), centroid the texel centre and second moment h²/3; convolved
 * with G(v) the result has mass h², the same centroid and second moment 2v + h²/3. Measured
 * by summing S over a grid of targets finer than both σ and h. Tolerances, per path:
 * - narrow (sub-triangles, here of edge σ/16): the midpoint rule across the tent's kinks,
 *   O((s/h)²): mass 2e-3, centroid 1e-3 h, second moment 1 %;
 * - wide (one point per piece of the cells between texel centres): exact for the mass of a
 *   bilinear function; a piece split by a triangle edge moves the tent's first moment by
 *   h/16 at most (midpoint rule on the two halves of one linear ramp: 1/12 − 2/48), so the
 *   centroid within h/16 + 1e-3 h, mass 1e-3, second moment 1 %. */
Test(reference, delta_moments)
{
    dm_mesh m;
    grid_mesh(8, 8, plane_pos, uv_id, &m);
    enum { NA = 256 };
    float *a = atlas_from(NA, one);
    for (size_t i = 0; i < (size_t)NA * NA; ++i) a[4 * i] = a[4 * i + 1] = a[4 * i + 2] = 0.0f;
    int ci = 128, cj = 131;
    float *d = a + 4 * ((size_t)cj * NA + ci);
    d[0] = d[1] = d[2] = 1.0f;
    double h = PLANE_MM / NA, cx = (ci + 0.5) * h, cy = (cj + 0.5) * h;
    dm_profile p;
    dm_profile_gems3_skin(&p);
    for (int kk = 0; kk < 6; ++kk) {
        dm_reference_kernel k = {.count = 1};
        k.variance_mm2[0] = p.variance_mm2[kk];
        k.weight[0][0] = k.weight[0][1] = k.weight[0][2] = 1.0;
        dm_reference_options o = {.spacing_sigma = 1.0 / 16.0};
        dm_reference *ref = make_ref(&m, 1.0, NA, a, &k, &o);
        double sigma = sqrt(k.variance_mm2[0]);
        double step = fmin(sigma, h) / 2.0, half = 5.0 * sigma + 2.0 * h;
        int n = (int)ceil(2.0 * half / step);
        dm_reference_target *t = malloc(sizeof *t * (size_t)n * n);
        double *px = malloc(sizeof *px * (size_t)n * n * 2);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                double x = cx - half + (i + 0.5) * step, y = cy - half + (j + 0.5) * step;
                t[j * n + i] = plane_target(8, x, y);
                px[2 * (j * n + i)] = x, px[2 * (j * n + i) + 1] = y;
            }
        float *rgb = malloc(sizeof *rgb * 3 * (size_t)n * n);
        eval(ref, t, (size_t)n * n, rgb, NULL);
        double mass = 0, mx = 0, my = 0, m2 = 0;
        for (int i = 0; i < n * n; ++i) {
            double w = rgb[3 * i] * step * step;
            mass += w;
            mx += w * px[2 * i];
            my += w * px[2 * i + 1];
        }
        mx /= mass, my /= mass;
        for (int i = 0; i < n * n; ++i) {
            double dx = px[2 * i] - mx, dy = px[2 * i + 1] - my;
            m2 += rgb[3 * i] * step * step * (dx * dx + dy * dy);
        }
        m2 /= mass;
        double want_m2 = 2.0 * k.variance_mm2[0] + h * h / 3.0;
        cr_log_info("delta v %g: mass %.2e, centroid (%.2e, %.2e) h, second moment %.2e", k.variance_mm2[0],
                    mass / (h * h) - 1.0, (mx - cx) / h, (my - cy) / h, m2 / want_m2 - 1.0);
        dm_reference_stats st;
        dm_reference_get_stats(ref, &st);
        bool wide = st.wide_gaussians == 1;
        double tol_c = (wide ? 1.0 / 16.0 + 1e-3 : 1e-3) * h;
        cr_expect(fabs(mass / (h * h) - 1.0) < (wide ? 1e-3 : 2e-3), "v %g: mass %.6f h^2", k.variance_mm2[0], mass / (h * h));
        cr_expect(fabs(mx - cx) < tol_c && fabs(my - cy) < tol_c, "centroid (%.5f, %.5f) want (%.5f, %.5f)", mx, my,
                  cx, cy);
        cr_expect(fabs(m2 / want_m2 - 1.0) < 0.01, "v %g: second moment %.6f want %.6f", k.variance_mm2[0], m2, want_m2);
        free(rgb);
        free(px);
        free(t);
        dm_reference_destroy(ref);
    }
    free(a);
    dm_mesh_free(&m);
}

/* ---- sphere ------------------------------------------------------------------------ */

static double linear_z(double u, double v)
{
    (void)u;
    return 1.0 + 0.01 * (-SPHERE_MM * cos(DM_PI * v)); /* 1 + 0.01·z, z in mm */
}

/* On a sphere of radius R with I = a + b·z, chord distances give (Archimedes: the cap
 * within chord d has area πd²), with c = R²/v and E = 1 − e^{−2c}:
 *   S(x) = a·E + b·z_x·(E − (1 − (1 + 2c)e^{−2c})/c).
 * The mesh is a 256×128 lat-long polyhedron: its area falls short of the sphere's by
 * about (e/R)²/12 ≈ 5e-5 relative (e = 0.49 mm edges), the poles are degenerate
 * triangles and u = 0/1 is a seam the convolution crosses. Tolerance 2e-4 relative. */
Test(reference, sphere_linear)
{
    dm_mesh m;
    grid_mesh(256, 128, sphere_pos, uv_id, &m);
    enum { NA = 512 };
    float *a = atlas_from(NA, linear_z);
    dm_reference_kernel k;
    gems3_kernel(&k);
    dm_reference *ref = make_ref(&m, 1.0, NA, a, &k, NULL);
    enum { N = 6 };
    /* cell centres near the seam (u ≈ 0), the equator, and high latitudes */
    const double su[N] = {0.0005, 0.9995, 0.25, 0.5, 0.71, 0.1}, sv[N] = {0.5, 0.31, 0.85, 0.12, 0.5, 0.93};
    dm_reference_target t[N];
    for (int i = 0; i < N; ++i) {
        double s = su[i] * 256, tt = sv[i] * 128;
        int ii = (int)s, jj = (int)tt;
        double fs = s - ii, ft = tt - jj;
        if (fs >= ft) t[i] = (dm_reference_target){2 * (jj * 256 + ii), (float)(fs - ft), (float)ft};
        else t[i] = (dm_reference_target){2 * (jj * 256 + ii) + 1, (float)fs, (float)(ft - fs)};
    }
    float rgb[N * 3], lv[N * 6 * 3];
    eval(ref, t, N, rgb, lv);
    for (int i = 0; i < N; ++i) {
        double z = -SPHERE_MM * cos(DM_PI * sv[i]);
        for (int kk = 0; kk < 6; ++kk) {
            double v = k.variance_mm2[kk], c = SPHERE_MM * SPHERE_MM / v, E = -expm1(-2.0 * c);
            double want = E + 0.01 * z * (E - (1.0 - (1.0 + 2.0 * c) * exp(-2.0 * c)) / c);
            double got = lv[(i * 6 + kk) * 3];
            cr_expect(fabs(got / want - 1.0) < 2e-4, "(%.4f, %.2f) S%d %.7f want %.7f", su[i], sv[i], kk, got, want);
        }
    }
    dm_reference_destroy(ref);
    free(a);
    dm_mesh_free(&m);
}

/* ---- hard cases: finite output, a test each ------------------------------------------ */

static void expect_finite(const float *v, size_t n, const char *what)
{
    for (size_t i = 0; i < n; ++i) cr_assert(isfinite(v[i]) && v[i] >= 0.0f, "%s[%zu] = %g", what, i, v[i]);
}

/* Degenerate triangles (zero 3-D area: a collapsed corner; zero UV area: the head's eyes
 * have 11) added to a plane: finite everywhere, the zero-area ones carry no mass, the
 * zero-UV-area one carries its area (the plane's constant I is read at its UV). */
Test(reference, degenerate_triangles)
{
    dm_mesh plane, m;
    grid_mesh(4, 4, plane_pos, uv_id, &plane);
    dm_error err = {0};
    int nt = plane.triangle_count + 2;
    cr_assert_eq(dm_mesh_alloc(plane.vertex_count + 3, nt, &m, &err), DM_OK);
    memcpy(m.positions, plane.positions, sizeof(float) * 3 * (size_t)plane.vertex_count);
    memcpy(m.indices, plane.indices, sizeof(uint32_t) * 3 * (size_t)plane.triangle_count);
    memcpy(m.uvs, plane.uvs, sizeof(float) * 6 * (size_t)plane.triangle_count);
    memcpy(m.normals, plane.normals, sizeof(float) * 9 * (size_t)plane.triangle_count);
    int v = plane.vertex_count;
    const float extra[3][3] = {{32, 32, 1}, {33, 32, 1}, {32, 33, 1}}; /* a 0.5 mm² flap above the plane */
    memcpy(m.positions + 3 * v, extra, sizeof extra);
    int t0 = plane.triangle_count;
    /* zero 3-D area: all three corners on one vertex; zero UV area: every corner at one UV */
    uint32_t idx[2][3] = {{(uint32_t)v, (uint32_t)v, (uint32_t)v}, {(uint32_t)v, (uint32_t)v + 1, (uint32_t)v + 2}};
    for (int k = 0; k < 2; ++k)
        for (int c = 0; c < 3; ++c) {
            m.indices[3 * (t0 + k) + c] = idx[k][c];
            m.uvs[6 * (t0 + k) + 2 * c] = 0.5f, m.uvs[6 * (t0 + k) + 2 * c + 1] = 0.5f;
            m.normals[9 * (t0 + k) + 3 * c + 2] = 1.0f;
        }
    float *a = atlas_from(64, one);
    dm_reference_kernel k;
    gems3_kernel(&k);
    dm_reference *ref = make_ref(&m, 1.0, 64, a, &k, NULL);
    dm_reference_stats st;
    dm_reference_get_stats(ref, &st);
    cr_expect_eq(st.zero_area_triangles, 1);
    cr_expect_eq(st.zero_uv_area_triangles, 2);
    cr_expect(fabs(st.surface_area_mm2 - (PLANE_MM * PLANE_MM + 0.5)) < 1e-6, "area %.9g", st.surface_area_mm2);
    dm_reference_target t[3] = {plane_target(4, 32.2, 32.3), {t0, 0.3f, 0.3f}, {t0 + 1, 0.2f, 0.5f}};
    float rgb[9];
    eval(ref, t, 3, rgb, NULL);
    expect_finite(rgb, 9, "D");
    /* the flap 1 mm above adds its own light: more than the plane's 1, finite */
    cr_expect(rgb[0] > 1.0f && rgb[0] < 2.0f, "D on the plane under the flap %g", rgb[0]);
    dm_reference_destroy(ref);
    free(a);
    dm_mesh_free(&m);
    dm_mesh_free(&plane);
}

/* One triangle, and atlas texels with no surface under them (targets of the covered ones
 * only; an atlas with every alpha 0 has no targets and I = 0 everywhere). */
Test(reference, one_triangle_and_empty_texels)
{
    dm_mesh m;
    dm_error err = {0};
    cr_assert_eq(dm_mesh_alloc(3, 1, &m, &err), DM_OK);
    const float p[9] = {0, 0, 0, 10, 0, 0, 0, 10, 0}, uv[6] = {0.1f, 0.1f, 0.9f, 0.1f, 0.1f, 0.9f};
    memcpy(m.positions, p, sizeof p);
    memcpy(m.uvs, uv, sizeof uv);
    for (int c = 0; c < 3; ++c) m.normals[3 * c + 2] = 1.0f;
    float *a = atlas_from(32, one);
    dm_reference_kernel k;
    gems3_kernel(&k);
    dm_reference_atlas atlas = {32, 32, a};
    dm_reference_target *tg;
    int64_t *of;
    size_t n;
    cr_assert_eq(dm_reference_atlas_targets(&m, &atlas, 0, &tg, &of, &n, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(n, 32 * 32, "every texel is covered in this atlas: each gets a target on the triangle");
    dm_reference *ref = make_ref(&m, 1.0, 32, a, &k, NULL);
    float *rgb = malloc(sizeof *rgb * 3 * n);
    eval(ref, tg, n, rgb, NULL);
    expect_finite(rgb, 3 * n, "D");
    /* inside, far from the edges, a constant stays 1 (within the wide path's 4e-3 at 1.1
     * texels); at the corners the surface ends and less arrives */
    dm_reference_destroy(ref);
    free(rgb);
    free(tg);
    free(of);
    for (size_t i = 0; i < 32 * 32; ++i) a[4 * i + 3] = 0.0f;
    cr_assert_eq(dm_reference_atlas_targets(&m, &atlas, 0, &tg, &of, &n, &err), DM_OK, "%s", err.detail);
    cr_expect_eq(n, 0);
    ref = make_ref(&m, 1.0, 32, a, &k, NULL);
    dm_reference_target c = {0, 0.3f, 0.3f};
    float d[3];
    eval(ref, &c, 1, d, NULL);
    cr_expect(d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f, "no covered texel: I = 0, D = 0 (%g)", d[0]);
    dm_reference_stats st;
    dm_reference_get_stats(ref, &st);
    cr_expect(st.unlit_area_mm2 >= 0.0);
    dm_reference_destroy(ref);
    free(tg);
    free(of);
    free(a);
    dm_mesh_free(&m);
}

/* mm_per_unit 1e-6 (the 64-unit plane is 64 nm: every Gaussian covers it many times over,
 * D ≈ total flux × G(0) ≪ 1) and 1e6 (64 km: every Gaussian is far below a texel, D = I):
 * finite, and the limits hold. Invalid values are refused. */
Test(reference, extreme_mm_per_unit)
{
    dm_mesh m;
    grid_mesh(4, 4, plane_pos, uv_id, &m);
    float *a = atlas_from(64, one);
    dm_reference_kernel k;
    gems3_kernel(&k);
    dm_reference_target t = plane_target(4, 30.1, 33.7);
    float rgb[3];
    dm_reference *ref = make_ref(&m, 1e-6, 64, a, &k, NULL);
    eval(ref, &t, 1, rgb, NULL);
    expect_finite(rgb, 3, "tiny");
    double flux = PLANE_MM * PLANE_MM * 1e-12, want = 0.0;
    for (int i = 0; i < k.count; ++i) want += k.weight[i][0] * (flux / (DM_2PI * k.variance_mm2[i]) + exp(-8.0));
    cr_expect(fabs(rgb[0] / want - 1.0) < 1e-3, "tiny: D %g want %g", rgb[0], want);
    dm_reference_destroy(ref);
    ref = make_ref(&m, 1e6, 64, a, &k, NULL);
    eval(ref, &t, 1, rgb, NULL);
    expect_finite(rgb, 3, "huge");
    cr_expect(fabs(rgb[0] - 1.0) < 1e-3, "huge: D %g want 1", rgb[0]);
    dm_reference_destroy(ref);
    dm_error err = {0};
    dm_reference *bad = NULL;
    dm_reference_atlas atlas = {64, 64, a};
    cr_expect_eq(dm_reference_create(&m, 0.0, &atlas, &k, NULL, &bad, &err), DM_ERR_RANGE);
    cr_expect_eq(dm_reference_create(&m, NAN, &atlas, &k, NULL, &bad, &err), DM_ERR_RANGE);
    cr_expect_eq(dm_reference_create(&m, INFINITY, &atlas, &k, NULL, &bad, &err), DM_ERR_RANGE);
    cr_expect(bad == NULL);
    free(a);
    dm_mesh_free(&m);
}

/* Huge HDR irradiance (1e30) stays finite; 1 and 2 threads give the same bytes. */
static double huge(double u, double v) { return 1e30 * (1.0 + u + v); }
Test(reference, huge_values_and_threads)
{
    dm_mesh m;
    grid_mesh(8, 8, plane_pos, uv_id, &m);
    float *a = atlas_from(128, huge);
    dm_reference_kernel k;
    gems3_kernel(&k);
    enum { N = 64 };
    dm_reference_target t[N];
    for (int i = 0; i < N; ++i) t[i] = plane_target(8, 1.0 + i * 0.97, 2.0 + i * 0.91);
    float r1[N * 3], r2[N * 3], l1[N * 18], l2[N * 18];
    dm_reference_options o1 = {.thread_count = 1}, o2 = {.thread_count = 2};
    dm_reference *a1 = make_ref(&m, 1.0, 128, a, &k, &o1), *a2 = make_ref(&m, 1.0, 128, a, &k, &o2);
    eval(a1, t, N, r1, l1);
    eval(a2, t, N, r2, l2);
    expect_finite(r1, N * 3, "D");
    cr_expect(!memcmp(r1, r2, sizeof r1) && !memcmp(l1, l2, sizeof l1), "thread counts differ");
    /* a split of the targets (tiles) gives the same values */
    eval(a2, t + 10, N - 10, r2, NULL);
    cr_expect(!memcmp(r1 + 30, r2, sizeof(float) * 3 * (N - 10)), "a split differs");
    dm_reference_destroy(a1);
    dm_reference_destroy(a2);
    free(a);
    dm_mesh_free(&m);
}

/* Convergence on texel-level detail (what a normal map puts into irradiance): I = 1 + ½·noise
 * per texel. The default quadrature against one four times finer in σ (spacing σ/16 instead
 * of ~σ/3, so its own error is ~100× smaller): D agrees to 2e-3 relative at every target. */
static double noise(double u, double v)
{
    uint32_t h = (uint32_t)(u * 65536.0) * 2654435761u ^ (uint32_t)(v * 65536.0) * 40503u;
    h ^= h >> 13, h *= 0x5bd1e995u, h ^= h >> 15;
    return 1.0 + 0.5 * (double)(h & 0xffff) / 65535.0;
}
Test(reference, converged_on_texel_noise)
{
    dm_mesh m;
    grid_mesh(8, 8, plane_pos, uv_id, &m);
    float *a = atlas_from(128, noise); /* 0.5 mm texels, as the head's at 1024² */
    dm_reference_kernel k;
    gems3_kernel(&k);
    enum { N = 12 };
    dm_reference_target t[N];
    for (int i = 0; i < N; ++i) t[i] = plane_target(8, 14.1 + 3.07 * i, 40.3 - 1.9 * i);
    dm_reference_options fine = {.spacing_sigma = 1.0 / 16.0, .wide_texels = INFINITY};
    dm_reference *r0 = make_ref(&m, 1.0, 128, a, &k, NULL), *r1 = make_ref(&m, 1.0, 128, a, &k, &fine);
    float d0[N * 3], d1[N * 3];
    eval(r0, t, N, d0, NULL);
    eval(r1, t, N, d1, NULL);
    double worst = 0.0;
    for (int i = 0; i < N * 3; ++i) worst = fmax(worst, fabs(d0[i] / d1[i] - 1.0));
    cr_log_info("texel noise: default vs sigma/16 quadrature, worst relative difference %.2e", worst);
    cr_expect(worst < 2e-3, "worst %.2e", worst);
    dm_reference_destroy(r0);
    dm_reference_destroy(r1);
    free(a);
    dm_mesh_free(&m);
}

/* A dipole (Jensen 2001's skin1) is no sum of six Gaussians: the reference represents it
 * densely (12 log-spaced widths, NNLS weights). Its relative L2 error must be far below
 * what a 6-Gaussian fit of the same dipole leaves (1.9e-3 in dermis-fit-profile's table),
 * and on a plane the constant irradiance is preserved by the normalised kernel. */
#include "bake/dm_profile_fit.h"
Test(reference, dipole_kernel)
{
    dm_profile_source src = {.kind = DM_SOURCE_MEDIUM};
    dm_error err = {0};
    cr_assert_eq(dm_medium_preset("skin1", &src.medium, &err), DM_OK);
    dm_reference_kernel k;
    double e[3];
    cr_assert_eq(dm_reference_kernel_from_source(&src, 12, &k, e, &err), DM_OK, "%s", err.detail);
    cr_log_info("skin1 dipole in 12 Gaussians: relative L2 error %.2e %.2e %.2e, sigma %.3g..%.3g mm", e[0], e[1], e[2],
                sqrt(k.variance_mm2[0]), sqrt(k.variance_mm2[11]));
    dm_fit_result fit;
    cr_assert_eq(dm_profile_fit(&src, &(dm_fit_options){.gaussian_count = 6}, "fit6", &fit, &err), DM_OK);
    for (int c = 0; c < 3; ++c) {
        cr_expect(e[c] < 0.25 * fit.error_relative[c], "channel %d: %.2e vs the 6-Gaussian fit's %.2e", c, e[c],
                  fit.error_relative[c]);
        double sum = 0.0;
        for (int i = 0; i < k.count; ++i) sum += k.weight[i][c];
        cr_expect(fabs(sum - 1.0) < 1e-12);
    }
    cr_expect_eq(dm_reference_kernel_from_source(&src, 1, &k, e, &err), DM_ERR_RANGE);
}
