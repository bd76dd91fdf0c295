#include "reference/dm_ref_shade.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mesh/dm_uv_raster.h"
#include "core/dm_brdf.h"
#include "core/dm_parallel.h"
#include "core/dm_sh.h"

#define PI 3.14159265358979323846

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

void dm_ref_shade_light_dir(const dm_ref_surface *s, const dm_ref_point *p, int light, double L[3])
{
    const double *l = s->light_pos[light];
    if (l[3] == 0.0) {
        memcpy(L, l, 3 * sizeof *L);
        return;
    }
    double d[3] = {l[0] - p->p_mm[0], l[1] - p->p_mm[1], l[2] - p->p_mm[2]}, dl = dot3(d, d);
    if (dl > 1e-20) {
        for (int c = 0; c < 3; ++c) L[c] = d[c] / sqrt(dl);
    } else {
        L[0] = 0, L[1] = 0, L[2] = 1;
    }
}

double dm_ref_shade_visibility(const dm_ref_surface *s, const dm_ref_point *p, int light)
{
    if (!s->light_shadow[light]) return 1.0;
    /* from the smooth surface, not the facet: where the facet turns from a light its
     * interpolated normals still face, a ray from the facet hits the mesh beside it (the
     * terminator band); offset along the front normal, never through to the back, so a
     * concave wall still shadows itself where its normals turn from the light */
    double org[3], L[3], t_far = INFINITY;
    dm_ref_surface_smooth_point(s, p, org);
    for (int c = 0; c < 3; ++c) org[c] += p->ng[c] * s->eps_mm;
    const double *l = s->light_pos[light];
    if (l[3] == 0.0) {
        memcpy(L, l, sizeof L);
    } else {
        double d[3] = {l[0] - org[0], l[1] - org[1], l[2] - org[2]}, dl = sqrt(dot3(d, d));
        if (!(dl > s->eps_mm)) return 1.0; /* the light sits on the surface */
        for (int c = 0; c < 3; ++c) L[c] = d[c] / dl;
        t_far = dl - s->eps_mm;
    }
    return dm_raycast_occluded(s->rays, org, L, 0.0, t_far) ? 0.0 : 1.0;
}

/* dm_env_rotate of common.glsl. */
static void env_rotate(double rot, const double d[3], double out[3])
{
    double c = cos(rot), sn = sin(rot);
    out[0] = c * d[0] - sn * d[2];
    out[1] = d[1];
    out[2] = sn * d[0] + c * d[2];
}

void dm_ref_shade_irradiance(const dm_ref_surface *s, const dm_ref_point *p, double e[3])
{
    e[0] = e[1] = e[2] = 0;
    for (int i = 0; i < s->light_count; ++i) {
        double L[3];
        dm_ref_shade_light_dir(s, p, i, L);
        double ndl = dot3(p->N, L);
        if (!(ndl > 0)) continue;
        double k = ndl * dm_ref_shade_visibility(s, p, i);
        if (s->terms.energy) {
            double f = 1.0 - p->rho_s * dm_ref_surface_rho_dt(s, ndl, p->m);
            k *= f > 0 ? f : 0.0;
        }
        for (int c = 0; c < 3; ++c) e[c] += s->light_color[i][c] * k;
    }
    if (s->terms.env_diffuse) {
        double n[3], sh[9][3], irr[3];
        env_rotate(s->env_rotation_rad, p->N, n);
        for (int k = 0; k < 9; ++k)
            for (int c = 0; c < 3; ++c) sh[k][c] = s->desc.env_sh[k][c];
        dm_sh9_irradiance((const double(*)[3])sh, n, irr);
        for (int c = 0; c < 3; ++c) e[c] += s->scene.env_intensity * (irr[c] > 0 ? irr[c] : 0.0) / PI;
    }
}

void dm_ref_shade_env_lookup(const dm_ref_surface *s, const dm_ref_texture *t, const double d[3], double rgb[3])
{
    double r[3], rgba[4];
    env_rotate(s->env_rotation_rad, d, r);
    double y = r[1] > 1 ? 1 : r[1] < -1 ? -1 : r[1];
    double u = 0.5 + atan2(r[0], -r[2]) / (2 * PI), v = 0.5 + asin(y) / PI;
    dm_ref_texture_sample(t, u, v, rgba);
    memcpy(rgb, rgba, 3 * sizeof *rgb);
}

/* env_specular of final.glsl: linear between the two levels around m. */
static void env_specular(const dm_ref_surface *s, const double R[3], double m, double rgb[3])
{
    const dm_ref_surface_desc *d = &s->desc;
    int n = d->env_level_count;
    rgb[0] = rgb[1] = rgb[2] = 0;
    if (n <= 0) return;
    if (m <= d->env_level_m[0] || n == 1) {
        dm_ref_shade_env_lookup(s, &d->env_levels[0], R, rgb);
        return;
    }
    for (int k = 1; k < n; ++k)
        if (m <= d->env_level_m[k]) {
            double gap = (double)d->env_level_m[k] - d->env_level_m[k - 1];
            double t = (m - d->env_level_m[k - 1]) / (gap > 1e-6 ? gap : 1e-6), a[3], b[3];
            dm_ref_shade_env_lookup(s, &d->env_levels[k - 1], R, a);
            dm_ref_shade_env_lookup(s, &d->env_levels[k], R, b);
            for (int c = 0; c < 3; ++c) rgb[c] = a[c] + t * (b[c] - a[c]);
            return;
        }
    dm_ref_shade_env_lookup(s, &d->env_levels[n - 1], R, rgb);
}

void dm_ref_shade_specular(const dm_ref_surface *s, const dm_ref_point *p, const double V[3], double spec[3])
{
    spec[0] = spec[1] = spec[2] = 0;
    if (!s->terms.specular) return;
    for (int i = 0; i < s->light_count; ++i) {
        double L[3];
        dm_ref_shade_light_dir(s, p, i, L);
        if (!(dot3(p->N, L) > 0)) continue;
        double ks = dm_ks_specular(p->N, L, V, p->m, p->rho_s, DM_SKIN_F0);
        if (!(ks > 0)) continue;
        ks *= dm_ref_shade_visibility(s, p, i);
        for (int c = 0; c < 3; ++c) spec[c] += s->light_color[i][c] * ks;
    }
    if (s->terms.env_specular) {
        double ndv = dot3(p->N, V), R[3], env[3];
        ndv = ndv > 0 ? ndv : 0.0;
        double nv = dot3(p->N, V); /* reflect(−V, N) = −V + 2 (N·V) N */
        for (int c = 0; c < 3; ++c) R[c] = -V[c] + 2 * nv * p->N[c];
        env_specular(s, R, p->m, env);
        double k = s->scene.env_intensity * p->rho_s * dm_ref_surface_rho_dt(s, ndv, p->m);
        for (int c = 0; c < 3; ++c) spec[c] += k * env[c];
    }
}

/* ---- the atlas ---------------------------------------------------------------------- */

enum { BAND_ROWS = 32 };

typedef struct atlas_job {
    const dm_ref_surface *s;
    const int32_t *triangle_of;
    int size, row0;
    float *rgba;
} atlas_job;

/* Barycentrics (b1, b2) of uv in triangle t's UV image; clamped into the triangle. */
static void uv_barycentrics(const dm_mesh *m, int32_t t, double u, double v, double *b1, double *b2)
{
    const float *uv = m->uvs + (size_t)t * 6;
    double e1u = (double)uv[2] - uv[0], e1v = (double)uv[3] - uv[1];
    double e2u = (double)uv[4] - uv[0], e2v = (double)uv[5] - uv[1];
    double pu = u - uv[0], pv = v - uv[1], det = e1u * e2v - e2u * e1v;
    double x = 1.0 / 3, y = 1.0 / 3;
    if (det != 0) {
        x = (pu * e2v - e2u * pv) / det;
        y = (e1u * pv - pu * e1v) / det;
    }
    x = x > 0 ? (x < 1 ? x : 1) : 0;
    y = y > 0 ? (y < 1 ? y : 1) : 0;
    if (x + y > 1) {
        double sum = x + y;
        x /= sum;
        y /= sum;
    }
    *b1 = x;
    *b2 = y;
}

static void atlas_rows(void *ctx, size_t begin, size_t end)
{
    atlas_job *j = ctx;
    const dm_ref_surface *s = j->s;
    const double mix = s->scene.mix;
    for (size_t r = begin; r < end; ++r) {
        int row = j->row0 + (int)r;
        for (int i = 0; i < j->size; ++i) {
            size_t at = (size_t)row * (size_t)j->size + (size_t)i;
            float *o = j->rgba + at * 4;
            int32_t t = j->triangle_of[at];
            if (t < 0) {
                o[0] = o[1] = o[2] = o[3] = 0.0f;
                continue;
            }
            double b1, b2, e[3];
            uv_barycentrics(&s->mesh, t, (i + 0.5) / j->size, (row + 0.5) / j->size, &b1, &b2);
            dm_ref_point p;
            dm_ref_surface_point(s, t, b1, b2, &p);
            dm_ref_shade_irradiance(s, &p, e);
            for (int c = 0; c < 3; ++c) {
                double v = e[c] * pow(p.albedo[c], mix);
                o[c] = isfinite(v) ? (float)(v < 3.0e38 ? v : 3.0e38) : 0.0f;
            }
            o[3] = 1.0f;
        }
    }
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

dm_result dm_ref_shade_atlas(const dm_ref_surface *s, int size, int thread_count, float *rgba,
                             dm_ref_atlas_stats *stats, void (*progress)(void *user, double fraction),
                             void *progress_user, dm_error *err)
{
    assert(s && rgba);
    double t0 = now_ms();
    if (size < 1 || size > DM_UV_RASTER_SIZE_MAX)
        return dm_fail(err, DM_ERR_RANGE, "irradiance atlas: size %d, expected 1..%d", size, DM_UV_RASTER_SIZE_MAX);
    int32_t *tri = malloc((size_t)size * (size_t)size * sizeof *tri);
    if (!tri) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "irradiance atlas: cannot allocate %dx%d", size, size);
    dm_uv_raster_stats rs;
    dm_result r = dm_uv_raster(&s->mesh, NULL, size, size, thread_count, tri, &rs, err);
    if (r != DM_OK) {
        free(tri);
        return r;
    }
    atlas_job j = {s, tri, size, 0, rgba};
    for (int row0 = 0; row0 < size; row0 += BAND_ROWS) {
        int rows = size - row0 < BAND_ROWS ? size - row0 : BAND_ROWS;
        j.row0 = row0;
        dm_parallel_for((size_t)rows, 1, thread_count, atlas_rows, &j);
        if (progress) progress(progress_user, (double)(row0 + rows) / size);
    }
    if (stats) {
        stats->covered_texels = rs.covered_texels;
        stats->ms = now_ms() - t0;
    }
    free(tri);
    return DM_OK;
}
