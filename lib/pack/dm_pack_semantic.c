/* dm_pack_semantic.c — the physical ranges of every pack entry's values (dm_pack_semantic.h),
 * one rule per entry kind, each over the whole blob. */
#include "pack/dm_pack_semantic.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "pack/dm_pack_query.h"
#include "pack/dm_pack_needs.h"
#include "core/dm_ssss_kernel.h"

typedef struct ctx {
    const dm_pack *pack;
    const dm_pack_entry *e;
    const dm_scene *scene;
    dm_error *err;
} ctx;

/* "FILE: entry "NAME"" in front of every message. */
#define FAIL(c, code, fmt, ...) \
    dm_fail((c)->err, code, "%s: entry \"%s\": " fmt, (c)->pack->what, (c)->e->name, __VA_ARGS__)

/* A closed range [lo, hi], or (lo, hi] when lo_open, and why it is the range. */
typedef struct range {
    double lo, hi;
    bool lo_open;
    const char *why;
} range;

/* Every float of a single-level float32 texture; comp[c] is component c's range. Blocks of
 * BLOCK floats are tested without a branch (the compiler vectorises it), and only a failing
 * block again, for the first value outside. NaN is outside every range. */
enum { BLOCK = 1024 };
static dm_result texels_in(const ctx *c, const range *comp)
{
    const dm_pack_entry *e = c->e;
    const dm_tex_format_info *f = dm_tex_format_get(e->format);
    const float *v = e->data; /* 64-byte aligned, level 0 first */
    const int k = f->components;
    const uint64_t n = (uint64_t)e->width * (uint64_t)e->height * (uint64_t)e->layers * (uint64_t)k;
    float lo[4], hi[4]; /* component i % 4 of a block (BLOCK and 4 are multiples of k) */
    for (int q = 0; q < 4; ++q) {
        const range *r = &comp[q % k];
        lo[q] = r->lo_open ? nextafterf((float)r->lo, INFINITY) : (float)r->lo;
        hi[q] = (float)r->hi;
    }
    for (uint64_t b = 0; b < n; b += BLOCK) {
        uint64_t end = n - b < BLOCK ? n : b + BLOCK;
        int bad = 0;
        if (end - b == BLOCK)
            for (uint64_t i = b; i < end; i += 4)
                for (int q = 0; q < 4; ++q) bad |= !(v[i + q] >= lo[q] && v[i + q] <= hi[q]);
        else
            bad = 1; /* the last, partial block: the slow scan below */
        for (uint64_t i = b; bad && i < end; ++i) {
            if (v[i] >= lo[i % 4] && v[i] <= hi[i % 4]) continue;
            const range *r = &comp[i % (uint64_t)k];
            uint64_t texel = i / (uint64_t)k, plane = (uint64_t)e->width * (uint64_t)e->height, in = texel % plane;
            return FAIL(c, DM_ERR_RANGE,
                        "texel (%" PRIu64 ", %" PRIu64 ") of layer %" PRIu64 ", component %d is %g, expected %c%g, %g] "
                        "(%s)",
                        in % (uint64_t)e->width, in / (uint64_t)e->width, texel / plane, (int)(i % (uint64_t)k),
                        (double)v[i], r->lo_open ? '(' : '[', r->lo, r->hi, r->why);
        }
    }
    return DM_OK;
}

/* The same range for every component. */
static dm_result all_texels_in(const ctx *c, range r)
{
    const range comp[4] = {r, r, r, r};
    return texels_in(c, comp);
}

static dm_result shape(const ctx *c, int layers_min, int layers_max, const char *why)
{
    const dm_pack_entry *e = c->e;
    if (e->levels != 1 || e->layers < layers_min || e->layers > layers_max) {
        if (layers_min == layers_max)
            return FAIL(c, DM_ERR_FORMAT, "%d levels and %d layers, expected 1 level and %d layer%s (%s)", e->levels,
                        e->layers, layers_min, layers_min == 1 ? "" : "s", why);
        return FAIL(c, DM_ERR_FORMAT, "%d levels and %d layers, expected 1 level and %d..%d layers (%s)", e->levels,
                    e->layers, layers_min, layers_max, why);
    }
    return DM_OK;
}

static dm_result single(const ctx *c)
{
    return shape(c, 1, 1, "the renderer reads one image");
}

/* --- the rules ---------------------------------------------------------------------- */

static double length3(const float *v)
{
    return sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
}

static dm_result vertices(const ctx *c)
{
    const dm_pack_entry *v, *ix;
    dm_result r = dm_pack_mesh(c->pack, &v, &ix, c->err);
    if (r != DM_OK) return r;
    if (v->vertex_count < 3)
        return FAIL(c, DM_ERR_RANGE, "%" PRId64 " vertices, expected at least 3 (one triangle)", v->vertex_count);
    const double mm = c->scene->mm_per_unit, bound = DM_PACK_POSITION_MAX_MM / mm;
    for (int64_t i = 0; i < v->vertex_count; ++i) {
        const float *p = (const float *)v->data + i * (DM_PACK_VERTEX_STRIDE / 4);
        for (int d = 0; d < 3; ++d)
            if (!(fabs((double)p[d]) <= bound))
                return FAIL(c, DM_ERR_RANGE,
                            "vertex %" PRId64 ": position %c = %g (%g mm at mm_per_unit %g), expected within +-%g "
                            "(%g mm: no scene a pack holds is larger)",
                            i, "xyz"[d], (double)p[d], p[d] * mm, mm, bound, DM_PACK_POSITION_MAX_MM);
        static const struct {
            int offset;
            const char *name;
        } unit[2] = {{DM_PACK_VERTEX_NORMAL, "normal"}, {DM_PACK_VERTEX_TANGENT, "tangent"}};
        for (int u = 0; u < 2; ++u) {
            const float *n = p + unit[u].offset / 4;
            double len = length3(n);
            if (!(fabs(len - 1.0) <= DM_PACK_UNIT_TOLERANCE))
                return FAIL(c, DM_ERR_RANGE, "vertex %" PRId64 ": %s (%g, %g, %g) has length %g, expected 1 +- %g",
                            i, unit[u].name, (double)n[0], (double)n[1], (double)n[2], len, DM_PACK_UNIT_TOLERANCE);
        }
        float w = p[DM_PACK_VERTEX_TANGENT / 4 + 3];
        if (w != 1.0f && w != -1.0f)
            return FAIL(c, DM_ERR_RANGE, "vertex %" PRId64 ": tangent w = %g, expected +1 or -1 (the handedness)", i,
                        (double)w);
    }
    return DM_OK;
}

static dm_result directional(const ctx *c)
{
    dm_result r = single(c);
    return r != DM_OK ? r
                      : all_texels_in(c, (range){0.0, DM_PACK_DIRECTIONAL_MAX, false,
                                                 "a directional albedo or its split-sum parts: at most pi, "
                                                 "reached as m -> 0"});
}

static dm_result stretch(const ctx *c)
{
    int n = c->scene->profile.count;
    dm_result r = shape(c, n, n, "one layer per Gaussian of the scene's profile");
    return r != DM_OK ? r
                      : all_texels_in(c, (range){0.0, DM_PACK_STRETCH_MAX_PER_MM, true,
                                                 "UV units per mm: positive, gutters filled; more and the atlas would "
                                                 "span a nanometre"});
}

/* u', v' in [0, 1], the flag 0 or 1 (checked as [0, 1]), the distance beyond the edge in mm */
static dm_result seam(const ctx *c)
{
    dm_result r = single(c);
    const range comp[4] = {{0.0, 1.0, false, "a UV where the surface continues"},
                           {0.0, 1.0, false, "a UV where the surface continues"},
                           {0.0, 1.0, false, "1 continued, 0 not"},
                           {0.0, 1e6, false, "mm beyond the chart's edge"}};
    return r != DM_OK ? r : texels_in(c, comp);
}

/* N × 2N, candidate k of texel (i, j) in row k·N + j: u', v' in [0, 1], d in [0, reach] mm with
 * reach 3 σ of the scene profile's widest Gaussian (what the packer bakes with, as
 * bake/dm_seam_map.h's dm_seam_map_reach_mm; float rounding let through), the flag exactly 0
 * or 1, and a texel without a candidate all zeros. */
static dm_result thin(const ctx *c)
{
    const dm_pack_entry *e = c->e;
    dm_result r = single(c);
    if (r != DM_OK) return r;
    if (e->height != 2 * e->width)
        return FAIL(c, DM_ERR_FORMAT, "%dx%d, expected N x 2N (two candidates per texel, one above the other)",
                    e->width, e->height);
    const dm_profile *pf = &c->scene->profile;
    const double reach = 3.0 * sqrt(fmax(pf->variance_mm2[pf->count - 1], 0.0)) * (1 + 1e-6);
    const range comp[4] = {{0.0, 1.0, false, "a UV across the thin part"},
                           {0.0, 1.0, false, "a UV across the thin part"},
                           {0.0, reach, false, "mm across, within 3 sigma of the profile's widest Gaussian"},
                           {0.0, 1.0, false, "1 a candidate, 0 none"}};
    if ((r = texels_in(c, comp)) != DM_OK) return r;
    const float *v = e->data;
    for (uint64_t t = 0; t < (uint64_t)e->width * (uint64_t)e->height; ++t) {
        const float *px = v + 4 * t;
        if (px[3] == 1.0f || (px[3] == 0.0f && px[0] == 0.0f && px[1] == 0.0f && px[2] == 0.0f)) continue;
        return FAIL(c, DM_ERR_RANGE,
                    "texel (%" PRIu64 ", %" PRIu64 ") is (%g, %g, %g, %g), expected a candidate (u, v, mm, 1) or "
                    "none (0, 0, 0, 0)",
                    t % (uint64_t)e->width, t / (uint64_t)e->width, (double)px[0], (double)px[1], (double)px[2],
                    (double)px[3]);
    }
    return DM_OK;
}

/* The thin gather (bake/dm_thin_gather.h): the index's first tap's row and counts below 2^24 (a
 * float counts exactly there; checked as ranges), its column in [0, 4095]; the taps 4096 wide,
 * site indices, UVs and weights in [0, 2^24], the header's mark of the layout (−2) among them. */
static dm_result gather_index(const ctx *c)
{
    dm_result r = single(c);
    const range comp[4] = {{0.0, 16777216.0, false, "the first tap's row, below 2^24"},
                           {0.0, 16777216.0, false, "taps of the first gathered level"},
                           {0.0, 16777216.0, false, "taps of the second gathered level"},
                           {0.0, 4095.0, false, "the first tap's column"}};
    return r != DM_OK ? r : texels_in(c, comp);
}

static dm_result gather_taps(const ctx *c)
{
    dm_result r = single(c);
    if (r != DM_OK) return r;
    if (c->e->width != 4096) return FAIL(c, DM_ERR_FORMAT, "%d wide, expected 4096 taps a row", c->e->width);
    const range comp[2] = {{-2.0, 16777216.0, false, "a site's tap index or u (or the header), below 2^24"},
                           {0.0, 16777216.0, false, "a tap's weight or a site's v (or the header)"}};
    return texels_in(c, comp);
}

static dm_result kernel(const ctx *c)
{
    const dm_pack_entry *e = c->e;
    dm_result r = single(c);
    if (r != DM_OK) return r;
    const int rows_max = e->has_t_range ? DM_SSSS_MAX_ROWS : 1;
    if (e->height < 1 || e->height > rows_max || e->width < 3 || e->width > DM_SSSS_MAX_TAPS || e->width % 2 == 0)
        return FAIL(c, DM_ERR_FORMAT, "%dx%d, expected taps x rows with an odd number of taps in [3, %d] and 1 to %d "
                    "rows (%s)", e->width, e->height, DM_SSSS_MAX_TAPS, rows_max,
                    e->has_t_range ? "one per size of pixel" : "1 without \"t_range\", its sizes of pixel");
    dm_ssss_kernel k;
    dm_error inner = {0};
    if (dm_ssss_kernel_from_texels(e->data, e->width, e->height, e->has_t_range ? e->t_range : NULL, &k, &inner) !=
        DM_OK) /* "sss.kernel: ..." */
        return FAIL(c, inner.code, "%s", strncmp(inner.detail, "sss.kernel: ", 12) ? inner.detail : inner.detail + 12);
    return DM_OK;
}

static dm_result preintegrated(const ctx *c)
{
    const dm_pack_entry *e = c->e;
    dm_result r = single(c);
    if (r != DM_OK) return r;
    if (e->height < 2)
        return FAIL(c, DM_ERR_FORMAT, "height %d, expected 2 or more (flat and curved rows)", e->height);
    if (!e->has_t_range)
        return FAIL(c, DM_ERR_FORMAT, "%s",
                    "no \"t_range\" [0, curvature max] (its rows' curvature in 1/mm); pack the scene again with "
                    "this dermis-pack");
    if (e->t_range[0] != 0.0f || !(e->t_range[1] > 0.0f && e->t_range[1] <= DM_PACK_CURVATURE_MAX_PER_MM))
        return FAIL(c, DM_ERR_RANGE, "t_range [%g, %g], expected [0, max] with max in (0, %g] 1/mm (row 0 flat)",
                    (double)e->t_range[0], (double)e->t_range[1], DM_PACK_CURVATURE_MAX_PER_MM);
    return all_texels_in(c, (range){0.0, DM_PACK_PREINT_MAX, false, "a mean of max(0, N.L) over the profile"});
}

static dm_result sh(const ctx *c)
{
    const dm_pack_entry *e = c->e;
    if (e->sh_order != 2)
        return FAIL(c, DM_ERR_FORMAT, "order %d, expected 2 (9 RGB coefficients, what the renderer takes)",
                    e->sh_order);
    const float *v = e->data;
    for (int i = 0; i < 27; ++i) {
        bool dc = i < 3;
        if (dc ? !(v[i] >= 0.0f && v[i] <= DM_PACK_SH_MAX) : !(fabsf(v[i]) <= DM_PACK_SH_MAX))
            return FAIL(c, DM_ERR_RANGE, "coefficient %d channel %d is %g, expected %s%g%s (%s)", i / 3, i % 3,
                        (double)v[i], dc ? "[0, " : "within +-", DM_PACK_SH_MAX, dc ? "]" : "",
                        dc ? "the mean radiance times sqrt(4 pi)" : "radiance up to 1e18 times sqrt(4 pi)");
    }
    return DM_OK;
}

static const range radiance = {0.0, DM_PACK_RADIANCE_MAX, false, "radiance: what the environment loader takes"};

static dm_result specular(const ctx *c)
{
    const dm_pack_entry *e = c->e;
    dm_result r = shape(c, 1, DM_PACK_ENV_LEVELS_MAX, "one layer per prefiltered roughness");
    if (r != DM_OK) return r;
    if (e->layer_value_count != e->layers)
        return FAIL(c, DM_ERR_FORMAT,
                    "no \"layer_values\" (the Beckmann m of each of its %d layers); pack the scene again with this "
                    "dermis-pack",
                    e->layers);
    for (int k = 0; k < e->layers; ++k) {
        float m = e->layer_values[k];
        if (!(m >= (float)DM_PACK_ENV_M_MIN && m <= (float)DM_PACK_ENV_M_MAX))
            return FAIL(c, DM_ERR_RANGE, "layer_values[%d] = %g, expected a Beckmann m in [%g, %g]", k, (double)m,
                        DM_PACK_ENV_M_MIN, DM_PACK_ENV_M_MAX);
        if (k > 0 && !(m > e->layer_values[k - 1]))
            return FAIL(c, DM_ERR_RANGE, "layer_values[%d] = %g, expected more than layer_values[%d] = %g (ascending)",
                        k, (double)m, k - 1, (double)e->layer_values[k - 1]);
    }
    return all_texels_in(c, radiance);
}

static dm_result background(const ctx *c)
{
    dm_result r = single(c);
    return r != DM_OK ? r : all_texels_in(c, radiance);
}

/* --- the table ---------------------------------------------------------------------- */

static const struct rule {
    const char *row; /* a dm_pack_needs row */
    dm_result (*check)(const ctx *c);
} rules[] = {
    {"mesh.vertices", vertices},       {"albedo", single},           {"normal", single},
    {"specular", single},              {"roughness", single},        {"lut.beckmann", single},
    {"lut.rho_dt", directional},       {"lut.env_brdf", directional}, {"stretch", stretch},
    {"stretch.mask", single},          {"seam", seam},               {"thin", thin},
    {"thin.half", thin},               {"gather.index", gather_index}, {"gather.taps", gather_taps},
    {"gather.half.index", gather_index}, {"gather.half.taps", gather_taps},
    {"sss.kernel", kernel},       {"sss.preintegrated", preintegrated},
    {"sss.curvature", single},         {"env.sh", sh},               {"env.specular", specular},
    {"env.background", background},
};

dm_result dm_pack_check_values(const dm_pack *pack, dm_error *err)
{
    if (!pack->scene) return dm_fail(err, DM_ERR_FORMAT, "%s: no scene entry, expected one", pack->what);
    for (int k = 0; k < pack->entry_count; ++k) {
        const dm_pack_entry *e = &pack->entries[k];
        const dm_pack_need *nd = dm_pack_need_find(e->name);
        if (!nd) continue; /* not a dermis entry: the format checks only */
        if (e->kind != nd->kind || (nd->format >= 0 && e->format != (dm_tex_format)nd->format))
            return dm_fail(err, DM_ERR_FORMAT, "%s: entry \"%s\" is %s%s%s, expected %s%s%s", pack->what, e->name,
                           dm_pack_kind_name(e->kind), e->kind == DM_PACK_TEXTURE ? " " : "",
                           e->kind == DM_PACK_TEXTURE ? dm_tex_format_get(e->format)->name : "",
                           dm_pack_kind_name(nd->kind), nd->format >= 0 ? " " : "",
                           nd->format >= 0 ? dm_tex_format_get((dm_tex_format)nd->format)->name : "");
        const ctx c = {pack, e, pack->scene, err};
        for (size_t q = 0; q < sizeof rules / sizeof rules[0]; ++q) {
            if (strcmp(rules[q].row, nd->entry) != 0) continue;
            dm_result r = rules[q].check(&c);
            if (r != DM_OK) return r;
        }
    }
    return DM_OK;
}
