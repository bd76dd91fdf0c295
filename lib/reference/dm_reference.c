/* dm_reference.c — the ground truth's set-up: kernel, positions in mm, the triangle grid,
 * the split of the Gaussians into narrow groups and one wide group. The grids are
 * dm_ref_grid.c, the irradiance lookup dm_ref_lookup.c, texel elements
 * dm_reference_elements.c, evaluation dm_reference_eval.c. */
#include "reference/dm_reference.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bake/dm_profile_fit.h"
#include "reference/dm_reference_impl.h"
#include "core/dm_math.h"
#include "core/dm_sort.h"

dm_result dm_reference_kernel_from_profile(const dm_profile *p, dm_reference_kernel *k, dm_error *err)
{
    dm_result r = dm_profile_validate(p, "profile", err);
    if (r != DM_OK) return r;
    memset(k, 0, sizeof *k);
    double sum[3];
    dm_profile_channel_sums(p, sum);
    for (int c = 0; c < 3; ++c)
        if (!(sum[c] > 0.0)) return dm_fail(err, DM_ERR_RANGE, "profile '%s': channel %d's weights sum to 0", p->name, c);
    k->count = p->count;
    for (int i = 0; i < p->count; ++i) {
        k->variance_mm2[i] = p->variance_mm2[i];
        for (int c = 0; c < 3; ++c) k->weight[i][c] = p->weight[i][c] / sum[c];
    }
    return DM_OK;
}

dm_result dm_reference_kernel_from_source(const dm_profile_source *s, int gaussian_count, dm_reference_kernel *k,
                                          double rel_error[3], dm_error *err)
{
    memset(k, 0, sizeof *k);
    if (gaussian_count < 2 || gaussian_count > DM_REFERENCE_GAUSSIANS_MAX)
        return dm_fail(err, DM_ERR_RANGE, "reference: %d Gaussians for a radial profile, expected 2..%d", gaussian_count,
                       DM_REFERENCE_GAUSSIANS_MAX);
    double e[3];
    dm_result r = dm_profile_represent(s, gaussian_count, k->variance_mm2, k->weight, e, err);
    if (r != DM_OK) return r;
    k->count = gaussian_count;
    for (int c = 0; c < 3; ++c) {
        double sum = 0.0;
        for (int i = 0; i < k->count; ++i) sum += k->weight[i][c];
        if (!(sum > 0.0)) return dm_fail(err, DM_ERR_RANGE, "reference: the radial profile's channel %d is zero", c);
        for (int i = 0; i < k->count; ++i) k->weight[i][c] /= sum;
        if (rel_error) rel_error[c] = e[c];
    }
    return DM_OK;
}

/* Every triangle goes into each cell its bounding box overlaps (two passes: count, fill),
 * in triangle order, so the lists are deterministic. */
static dm_result build_triangle_grid(dm_reference *ref, const double lo[3], const double hi[3], double cell_mm,
                                     dm_error *err)
{
    const dm_mesh *m = ref->mesh;
    dm_ref_grid *g = &ref->tri_grid;
    dm_ref_grid_init(g, lo, hi, cell_mm);
    int64_t cells = (int64_t)g->dim[0] * g->dim[1] * g->dim[2];
    g->start = calloc((size_t)cells + 1, sizeof *g->start);
    if (!g->start) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference: triangle grid of %lld cells", (long long)cells);
    for (int pass = 0; pass < 2; ++pass) {
        for (int32_t t = 0; t < m->triangle_count; ++t) {
            double blo[3] = {INFINITY, INFINITY, INFINITY}, bhi[3] = {-INFINITY, -INFINITY, -INFINITY};
            for (int c = 0; c < 3; ++c) {
                const double *p = ref->pos_mm + 3 * (size_t)m->indices[3 * (size_t)t + c];
                for (int a = 0; a < 3; ++a) {
                    blo[a] = fmin(blo[a], p[a]);
                    bhi[a] = fmax(bhi[a], p[a]);
                }
            }
            int l[3], h[3];
            dm_ref_grid_box(g, blo, bhi, l, h);
            for (int z = l[2]; z <= h[2]; ++z)
                for (int y = l[1]; y <= h[1]; ++y)
                    for (int x = l[0]; x <= h[0]; ++x) {
                        int64_t c = ((int64_t)z * g->dim[1] + y) * g->dim[0] + x;
                        if (pass == 0) g->start[c + 1]++;
                        else g->item[g->start[c]++] = t;
                    }
        }
        if (pass == 0) {
            for (int64_t c = 0; c < cells; ++c) g->start[c + 1] += g->start[c];
            g->item = malloc(sizeof *g->item * (size_t)(g->start[cells] ? g->start[cells] : 1));
            if (!g->item) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference: triangle grid lists");
        } else {
            for (int64_t c = cells; c > 0; --c) g->start[c] = g->start[c - 1]; /* fill advanced each start */
            g->start[0] = 0;
        }
    }
    return DM_OK;
}

/* ---- create ------------------------------------------------------------------------ */

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

/* The atlas texel's edge in mm, 95th percentile over triangles weighted by their UV area
 * (the coarsest texels the wide Gaussians' elements have to resolve). */
static double texel_size_mm(const dm_reference *ref)
{
    const dm_mesh *m = ref->mesh;
    double *s = malloc(sizeof *s * (size_t)m->triangle_count);
    if (!s) return 0.0;
    int n = 0;
    double texel_uv_area = 1.0 / ((double)ref->atlas.width * ref->atlas.height);
    for (int32_t t = 0; t < m->triangle_count; ++t) {
        double uva = fabs(dm_mesh_triangle_uv_area(m, t));
        if (!(uva > 0.0) || !(ref->tri_area[t] > 0.0)) continue;
        s[n++] = sqrt(ref->tri_area[t] / uva * texel_uv_area);
    }
    double r = 0.0;
    if (n > 0) {
        dm_sort_doubles(s, (size_t)n);
        r = s[(int)floor(0.95 * (n - 1))];
    }
    free(s);
    return r;
}

/* Narrow Gaussians (σ below wide_texels texels) in groups of σ ratio < 1.5; the rest in
 * one wide group on texel elements. */
static void plan_groups(dm_reference *ref)
{
    const dm_reference_kernel *k = &ref->kernel;
    double wide_from = ref->wide_texels * ref->stats.texel_mm;
    ref->group_count = 0;
    ref->wide_group = -1;
    int i = 0;
    while (i < k->count) {
        double s0 = sqrt(k->variance_mm2[i]);
        dm_ref_group *g = &ref->group[ref->group_count++];
        g->first = i;
        if (s0 >= wide_from && ref->stats.texel_mm > 0.0) {
            g->count = k->count - i;
            g->spacing_mm = 0.0;
            g->radius_mm = ref->cut_sigma * sqrt(k->variance_mm2[k->count - 1]);
            ref->wide_group = ref->group_count - 1;
            ref->stats.wide_gaussians = g->count;
            break;
        }
        int j = i + 1;
        while (j < k->count && sqrt(k->variance_mm2[j]) < 1.5 * s0 && sqrt(k->variance_mm2[j]) < wide_from) ++j;
        g->count = j - i;
        g->spacing_mm = ref->spacing_sigma * s0;
        g->radius_mm = ref->cut_sigma * sqrt(k->variance_mm2[j - 1]);
        ref->stats.narrow_gaussians += g->count;
        i = j;
    }
}

static dm_result check_inputs(const dm_mesh *mesh, double mm_per_unit, const dm_reference_atlas *atlas,
                              const dm_reference_kernel *kernel, const dm_reference_options *o, dm_error *err)
{
    if (!(mm_per_unit > 0.0) || !isfinite(mm_per_unit))
        return dm_fail(err, DM_ERR_RANGE, "reference: mm_per_unit %g is not a finite value > 0", mm_per_unit);
    if (atlas->width < 1 || atlas->height < 1 || atlas->width > 16384 || atlas->height > 16384 || !atlas->rgba)
        return dm_fail(err, DM_ERR_RANGE, "reference: atlas %dx%d is not 1..16384 per side", atlas->width,
                       atlas->height);
    if (kernel->count < 1 || kernel->count > DM_REFERENCE_GAUSSIANS_MAX)
        return dm_fail(err, DM_ERR_RANGE, "reference: %d Gaussians, expected 1..%d", kernel->count,
                       DM_REFERENCE_GAUSSIANS_MAX);
    for (int k = 0; k < kernel->count; ++k) {
        double v = kernel->variance_mm2[k];
        if (!(v > 0.0) || !isfinite(v) || (k > 0 && !(v > kernel->variance_mm2[k - 1])))
            return dm_fail(err, DM_ERR_RANGE, "reference: Gaussian %d's variance %g mm^2 is not finite, > 0 and ascending",
                           k, v);
        for (int c = 0; c < 3; ++c)
            if (!(kernel->weight[k][c] >= 0.0) || !isfinite(kernel->weight[k][c]))
                return dm_fail(err, DM_ERR_RANGE, "reference: Gaussian %d's weight %g is not finite and >= 0", k,
                               kernel->weight[k][c]);
    }
    if (o->cut_sigma != 0.0 && !(o->cut_sigma >= 2.0 && o->cut_sigma <= 8.0))
        return dm_fail(err, DM_ERR_RANGE, "reference: cut %g sigma is not in [2, 8]", o->cut_sigma);
    if (o->spacing_sigma != 0.0 && !(o->spacing_sigma >= 1.0 / 32.0 && o->spacing_sigma <= 1.0))
        return dm_fail(err, DM_ERR_RANGE, "reference: spacing %g sigma is not in [1/32, 1]", o->spacing_sigma);
    if (o->wide_texels != 0.0 && !(o->wide_texels >= 1.0))
        return dm_fail(err, DM_ERR_RANGE, "reference: wide_texels %g is not >= 1", o->wide_texels);
    return dm_mesh_validate(mesh, "reference mesh", err);
}

dm_result dm_reference_create(const dm_mesh *mesh, double mm_per_unit, const dm_reference_atlas *atlas,
                              const dm_reference_kernel *kernel, const dm_reference_options *opt,
                              dm_reference **out, dm_error *err)
{
    *out = NULL;
    dm_reference_options o = opt ? *opt : (dm_reference_options){0};
    dm_result r = check_inputs(mesh, mm_per_unit, atlas, kernel, &o, err);
    if (r != DM_OK) return r;
    double t0 = now_ms();
    dm_reference *ref = calloc(1, sizeof *ref);
    if (!ref) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference");
    ref->mesh = mesh;
    ref->atlas = *atlas;
    ref->kernel = *kernel;
    ref->opt = o;
    ref->cut_sigma = o.cut_sigma != 0.0 ? o.cut_sigma : 4.0;
    ref->spacing_sigma = o.spacing_sigma != 0.0 ? o.spacing_sigma : 0.3;
    ref->wide_texels = o.wide_texels != 0.0 ? o.wide_texels : 4.0;
    ref->tail_fraction = exp(-0.5 * ref->cut_sigma * ref->cut_sigma);
    r = dm_ref_premultiply(atlas, &ref->lookup, err);
    if (r != DM_OK) {
        dm_reference_destroy(ref);
        return r;
    }
    size_t nv = (size_t)mesh->vertex_count, nt = (size_t)mesh->triangle_count;
    ref->pos_mm = malloc(sizeof *ref->pos_mm * nv * 3);
    ref->tri_area = malloc(sizeof *ref->tri_area * nt);
    ref->tri_edge = malloc(sizeof *ref->tri_edge * nt);
    if (!ref->pos_mm || !ref->tri_area || !ref->tri_edge) {
        dm_reference_destroy(ref);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference: %zu vertices", nv);
    }
    double *lo = ref->lo_mm, *hi = ref->hi_mm;
    for (int a = 0; a < 3; ++a) {
        lo[a] = INFINITY;
        hi[a] = -INFINITY;
    }
    for (size_t i = 0; i < nv * 3; ++i) {
        ref->pos_mm[i] = (double)mesh->positions[i] * mm_per_unit;
        lo[i % 3] = fmin(lo[i % 3], ref->pos_mm[i]);
        hi[i % 3] = fmax(hi[i % 3], ref->pos_mm[i]);
    }
    double edge_sum = 0.0;
    for (size_t t = 0; t < nt; ++t) {
        const double *p[3];
        for (int c = 0; c < 3; ++c) p[c] = ref->pos_mm + 3 * (size_t)mesh->indices[3 * t + c];
        double e1[3], e2[3], e3[3], x[3];
        for (int a = 0; a < 3; ++a) {
            e1[a] = p[1][a] - p[0][a];
            e2[a] = p[2][a] - p[0][a];
            e3[a] = p[2][a] - p[1][a];
        }
        x[0] = e1[1] * e2[2] - e1[2] * e2[1];
        x[1] = e1[2] * e2[0] - e1[0] * e2[2];
        x[2] = e1[0] * e2[1] - e1[1] * e2[0];
        ref->tri_area[t] = 0.5 * sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        double l1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
        double l2 = sqrt(e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]);
        double l3 = sqrt(e3[0] * e3[0] + e3[1] * e3[1] + e3[2] * e3[2]);
        ref->tri_edge[t] = fmax(l1, fmax(l2, l3));
        edge_sum += ref->tri_edge[t];
        ref->stats.surface_area_mm2 += ref->tri_area[t];
        if (!(ref->tri_area[t] > 0.0)) ref->stats.zero_area_triangles++;
        if (dm_mesh_triangle_uv_area(mesh, (int32_t)t) == 0.0) ref->stats.zero_uv_area_triangles++;
    }
    r = build_triangle_grid(ref, lo, hi, edge_sum / (double)nt, err);
    if (r == DM_OK) {
        ref->stats.texel_mm = texel_size_mm(ref);
        plan_groups(ref);
        if (ref->wide_group >= 0) r = dm_ref_build_elements(ref, err);
    }
    if (r != DM_OK) {
        dm_reference_destroy(ref);
        return r;
    }
    ref->stats.element_count = ref->element_count;
    ref->stats.build_ms = now_ms() - t0;
    *out = ref;
    return DM_OK;
}

void dm_reference_destroy(dm_reference *ref)
{
    if (!ref) return;
    free(ref->pos_mm);
    free(ref->tri_area);
    free(ref->tri_edge);
    free(ref->element);
    free(ref->lookup.texel);
    dm_ref_grid_free(&ref->tri_grid);
    dm_ref_grid_free(&ref->element_grid);
    free(ref);
}

void dm_reference_get_stats(const dm_reference *ref, dm_reference_stats *stats)
{
    *stats = ref->stats;
}
