#include "bake/dm_env_bake.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/dm_env_sh.h"
#include "image/dm_exr.h"
#include "core/dm_cli.h"
#include "core/dm_parallel.h"

double dm_env_default_m(int k, int count)
{
    if (count <= 1) return DM_ENV_M_FIRST;
    return DM_ENV_M_FIRST + (DM_ENV_M_LAST - DM_ENV_M_FIRST) * k / (count - 1);
}

void dm_env_bake_free(dm_env_bake *bake)
{
    if (!bake) return;
    for (int k = 0; k < DM_ENV_LEVEL_MAX; ++k) free(bake->levels[k].rgb);
    free(bake->background);
    memset(bake, 0, sizeof *bake);
}

typedef struct bg_job {
    const dm_envmap *map;
    int width, height;
    double u_shift, lod;
    float *out;
} bg_job;

static void bg_rows(void *ctx, size_t begin, size_t end)
{
    const bg_job *job = ctx;
    for (size_t j = begin; j < end; ++j)
        for (int i = 0; i < job->width; ++i) {
            double rgb[3];
            dm_envmap_sample(job->map, (i + 0.5) / job->width + job->u_shift, (j + 0.5) / job->height, job->lod, rgb);
            float *o = job->out + ((size_t)j * job->width + i) * 3;
            for (int c = 0; c < 3; ++c) o[c] = (float)rgb[c];
        }
}

void dm_env_background(const dm_envmap *map, int width, double rotate_deg, int threads, float *out_rgb)
{
    assert(map && out_rgb && width >= 2);
    /* A whole number of texels of rotation shifts exactly; wrap the shift into [0, 1). */
    double shift = rotate_deg / 360.0;
    shift -= floor(shift);
    double lod = log2((double)map->width / width);
    bg_job job = {map, width, width / 2, shift, lod > 0.0 ? lod : 0.0, out_rgb};
    dm_parallel_for((size_t)(width / 2), 0, threads, bg_rows, &job);
}

static int all_finite(const float *p, size_t n)
{
    for (size_t k = 0; k < n; ++k)
        if (!isfinite(p[k])) return 0;
    return 1;
}

static void report(const dm_env_options *o, int done, int total)
{
    if (o->progress) o->progress(o->progress_ctx, (double)done / total);
}

dm_result dm_env_bake_run(const dm_envmap *map, const dm_env_options *options, dm_env_bake *out, dm_error *err)
{
    assert(map && map->level[0] && options && out);
    memset(out, 0, sizeof *out);
    dm_env_options o = *options;
    if (o.samples == 0) o.samples = DM_ENV_SAMPLES_DEFAULT;
    if (o.spec_size == 0) o.spec_size = DM_ENV_SPEC_SIZE_DEFAULT;
    if (o.background_width == 0) o.background_width = map->width;
    if (o.check_texels == 0) o.check_texels = DM_ENV_CHECK_TEXELS_DEFAULT;
    if (o.samples < 1 || o.samples > DM_ENV_SAMPLES_MAX)
        return dm_fail(err, DM_ERR_RANGE, "sample count %d: expected 1..%d", o.samples, DM_ENV_SAMPLES_MAX);
    if (o.spec_size < 4 || o.spec_size > DM_ENVMAP_SIZE_MAX)
        return dm_fail(err, DM_ERR_RANGE, "specular size %d: expected 4..%d", o.spec_size, DM_ENVMAP_SIZE_MAX);
    if (o.background_width < 4 || o.background_width > DM_ENV_BACKGROUND_MAX || o.background_width % 2)
        return dm_fail(err, DM_ERR_RANGE, "background width %d: expected an even number in 4..%d",
                       o.background_width, DM_ENV_BACKGROUND_MAX);
    if (!isfinite(o.rotate_deg)) return dm_fail(err, DM_ERR_RANGE, "rotation %g: expected a finite angle", o.rotate_deg);
    if (o.roughness_count > 0) {
        if (o.roughness_count > DM_ENV_LEVEL_MAX)
            return dm_fail(err, DM_ERR_RANGE, "%d roughness levels: expected 1..%d", o.roughness_count,
                           DM_ENV_LEVEL_MAX);
        for (int k = 0; k < o.roughness_count; ++k) {
            double m = o.roughness[k];
            if (!(m >= DM_ENV_M_MIN && m <= DM_ENV_M_MAX))
                return dm_fail(err, DM_ERR_RANGE, "roughness %g (level %d): expected %g..%g", m, k, DM_ENV_M_MIN,
                               DM_ENV_M_MAX);
            if (k > 0 && !(m > o.roughness[k - 1]))
                return dm_fail(err, DM_ERR_RANGE, "roughness %g (level %d): expected more than the previous %g", m,
                               k, o.roughness[k - 1]);
        }
        out->level_count = o.roughness_count;
    } else {
        if (o.level_count == 0) o.level_count = DM_ENV_LEVELS_DEFAULT;
        if (o.level_count < 1 || o.level_count > DM_ENV_LEVEL_MAX)
            return dm_fail(err, DM_ERR_RANGE, "level count %d: expected 1..%d", o.level_count, DM_ENV_LEVEL_MAX);
        out->level_count = o.level_count;
    }
    out->samples = o.samples;
    out->rotate_deg = o.rotate_deg;
    const int stages = 2 + 2 * out->level_count;
    int done = 0;
    report(&o, done, stages);

    double t0 = dm_now_ms();
    dm_result r = dm_env_project_sh9(map, o.rotate_deg, o.threads, out->sh, err);
    if (r != DM_OK) return r;
    out->sh_ms = dm_now_ms() - t0;
    for (int k = 0; k < DM_SH9_COUNT; ++k)
        for (int c = 0; c < 3; ++c)
            if (!isfinite(out->sh[k][c]))
                return dm_fail(err, DM_ERR_NON_FINITE, "SH coefficient %d channel %d is not finite", k, c);
    report(&o, ++done, stages);

    t0 = dm_now_ms();
    out->background_width = o.background_width;
    out->background_height = o.background_width / 2;
    size_t bg_n = (size_t)out->background_width * out->background_height * 3;
    out->background = malloc(bg_n * sizeof(float));
    if (!out->background)
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "background %dx%d: out of memory", out->background_width,
                       out->background_height);
    dm_env_background(map, out->background_width, o.rotate_deg, o.threads, out->background);
    if (!all_finite(out->background, bg_n))
        return dm_fail(err, DM_ERR_NON_FINITE, "background: a texel is not finite");
    out->background_ms = dm_now_ms() - t0;
    report(&o, ++done, stages);

    for (int k = 0; k < out->level_count; ++k) {
        dm_env_level *lv = &out->levels[k];
        lv->m = o.roughness_count > 0 ? o.roughness[k] : dm_env_default_m(k, out->level_count);
        lv->width = dm_env_level_width(lv->m, o.spec_size, map->width);
        lv->height = lv->width / 2;
        size_t n = (size_t)lv->width * lv->height * 3;
        lv->rgb = malloc(n * sizeof(float));
        if (!lv->rgb) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "level %d: out of memory", k);
        t0 = dm_now_ms();
        r = dm_env_prefilter(map, lv->m, o.samples, o.rotate_deg, lv->width, o.threads, lv->rgb, err);
        if (r != DM_OK) return r;
        lv->ms = dm_now_ms() - t0;
        out->prefilter_ms += lv->ms;
        if (!all_finite(lv->rgb, n))
            return dm_fail(err, DM_ERR_NON_FINITE, "prefiltered level %d (m = %g): a texel is not finite", k, lv->m);
        report(&o, ++done, stages);
        if (o.check_texels > 0) {
            dm_env_prefilter_error(map, lv->m, o.rotate_deg, lv->rgb, lv->width, o.check_texels, o.threads,
                                   &lv->error);
            out->check_ms += lv->error.ms;
        }
        report(&o, ++done, stages);
    }
    return DM_OK;
}

/* ---- the file ---------------------------------------------------------------------- */

static void level_name(char *out, size_t size, int k, const char *what)
{
    snprintf(out, size, "level%d_%s", k, what);
}

dm_result dm_env_write(const char *path, const dm_env_bake *bake, const dm_provenance *prov, dm_error *err)
{
    assert(path && bake && prov && bake->background);
    if (prov->param_count + DM_ENV_PROV_PARAMS > DM_PROV_PARAM_MAX)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: provenance has %d parameters, the layout needs %d more of %d",
                       path, prov->param_count, DM_ENV_PROV_PARAMS, DM_PROV_PARAM_MAX);
    dm_provenance p = *prov;
    int width = DM_SH9_COUNT, height = 1;
    if (bake->background_width > width) width = bake->background_width;
    int bg_y = height;
    height += bake->background_height;
    int level_y[DM_ENV_LEVEL_MAX];
    for (int k = 0; k < bake->level_count; ++k) {
        if (bake->levels[k].width > width) width = bake->levels[k].width;
        level_y[k] = height;
        height += bake->levels[k].height;
    }
    dm_prov_add_int(&p, "sh_y", 0);
    dm_prov_add_int(&p, "background_y", bg_y);
    dm_prov_add_int(&p, "background_width", bake->background_width);
    dm_prov_add_int(&p, "background_height", bake->background_height);
    dm_prov_add_int(&p, "level_count", bake->level_count);
    char name[DM_PROV_NAME_SIZE];
    for (int k = 0; k < bake->level_count; ++k) {
        const dm_env_level *lv = &bake->levels[k];
        level_name(name, sizeof name, k, "m");
        dm_prov_add_double(&p, name, lv->m);
        level_name(name, sizeof name, k, "y");
        dm_prov_add_int(&p, name, level_y[k]);
        level_name(name, sizeof name, k, "width");
        dm_prov_add_int(&p, name, lv->width);
        level_name(name, sizeof name, k, "error_rms");
        dm_prov_add_double(&p, name, lv->error.texels ? lv->error.rms_rel : -1.0);
        level_name(name, sizeof name, k, "error_max");
        dm_prov_add_double(&p, name, lv->error.texels ? lv->error.max_rel : -1.0);
    }
    size_t n = (size_t)width * height;
    float *planes = calloc(n * 3, sizeof(float));
    if (!planes) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory for %dx%d", path, width, height);
    for (int k = 0; k < DM_SH9_COUNT; ++k)
        for (int c = 0; c < 3; ++c) planes[c * n + k] = (float)bake->sh[k][c];
#define PUT_RECT(src, w, h, y0)                                                                        \
    for (int j = 0; j < (h); ++j)                                                                      \
        for (int i = 0; i < (w); ++i)                                                                  \
            for (int c = 0; c < 3; ++c)                                                                \
                planes[c * n + (size_t)((y0) + j) * width + i] = (src)[((size_t)j * (w) + i) * 3 + c];
    PUT_RECT(bake->background, bake->background_width, bake->background_height, bg_y)
    for (int k = 0; k < bake->level_count; ++k)
        PUT_RECT(bake->levels[k].rgb, bake->levels[k].width, bake->levels[k].height, level_y[k])
#undef PUT_RECT
    dm_exr_channel ch[3] = {{"R", planes, DM_EXR_FLOAT}, {"G", planes + n, DM_EXR_FLOAT},
                            {"B", planes + 2 * n, DM_EXR_FLOAT}};
    dm_result r = dm_exr_write(path, width, height, ch, 3, &p, err);
    free(planes);
    return r;
}

static dm_result get_int(const dm_provenance *p, const char *name, const char *path, int64_t lo, int64_t hi,
                         int *out, dm_error *err)
{
    const dm_param *q = dm_prov_find(p, name);
    if (!q || q->type != DM_PARAM_INT || q->i < lo || q->i > hi)
        return dm_fail(err, DM_ERR_FORMAT, "%s: attribute %s is %s: expected an integer in %lld..%lld", path, name,
                       q ? "of the wrong type or out of range" : "missing", (long long)lo, (long long)hi);
    *out = (int)q->i;
    return DM_OK;
}

static dm_result get_double(const dm_provenance *p, const char *name, const char *path, double *out, dm_error *err)
{
    const dm_param *q = dm_prov_find(p, name);
    if (!q || (q->type != DM_PARAM_DOUBLE && q->type != DM_PARAM_INT))
        return dm_fail(err, DM_ERR_FORMAT, "%s: attribute %s is missing or not a number", path, name);
    *out = q->type == DM_PARAM_INT ? (double)q->i : q->d;
    return DM_OK;
}

static dm_result copy_rect(const dm_exr_image *img, const float *planes[3], int w, int h, int y0, const char *what,
                           const char *path, float **out, dm_error *err)
{
    if (w < 1 || h < 1 || w > img->width || y0 < 0 || y0 + h > img->height)
        return dm_fail(err, DM_ERR_FORMAT, "%s: %s rectangle %dx%d at row %d lies outside the %dx%d image", path, what,
                       w, h, y0, img->width, img->height);
    *out = malloc((size_t)w * h * 3 * sizeof(float));
    if (!*out) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory for %s", path, what);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            for (int c = 0; c < 3; ++c)
                (*out)[((size_t)j * w + i) * 3 + c] = planes[c][(size_t)(y0 + j) * img->width + i];
    return DM_OK;
}

dm_result dm_env_read(const char *path, dm_env_bake *out, dm_provenance *prov, dm_error *err)
{
    assert(path && out);
    memset(out, 0, sizeof *out);
    dm_exr_image img;
    dm_result r = dm_exr_read(path, &img, err);
    if (r != DM_OK) {
        dm_exr_free(&img);
        return r;
    }
    const float *planes[3] = {dm_exr_find(&img, "R"), dm_exr_find(&img, "G"), dm_exr_find(&img, "B")};
    const dm_provenance *p = &img.prov;
    int bg_y = 0, bg_w = 0, bg_h = 0, sh_y = 0, count = 0;
    if (!planes[0] || !planes[1] || !planes[2] || !img.has_provenance || img.width < DM_SH9_COUNT)
        r = dm_fail(err, DM_ERR_FORMAT, "%s: expected R, G, B channels and dermis provenance of an environment bake",
                    path);
    if (r == DM_OK) r = get_int(p, "sh_y", path, 0, img.height - 1, &sh_y, err);
    if (r == DM_OK) r = get_int(p, "background_y", path, 0, img.height, &bg_y, err);
    if (r == DM_OK) r = get_int(p, "background_width", path, 1, img.width, &bg_w, err);
    if (r == DM_OK) r = get_int(p, "background_height", path, 1, img.height, &bg_h, err);
    if (r == DM_OK) r = get_int(p, "level_count", path, 1, DM_ENV_LEVEL_MAX, &count, err);
    if (r == DM_OK) {
        for (int k = 0; k < DM_SH9_COUNT; ++k)
            for (int c = 0; c < 3; ++c) out->sh[k][c] = planes[c][(size_t)sh_y * img.width + k];
        out->background_width = bg_w;
        out->background_height = bg_h;
        r = copy_rect(&img, planes, bg_w, bg_h, bg_y, "background", path, &out->background, err);
    }
    const dm_param *samples = dm_prov_find(p, "samples");
    if (samples && samples->type == DM_PARAM_INT) out->samples = (int)samples->i;
    const dm_param *rot = dm_prov_find(p, "rotate_deg");
    if (rot && rot->type != DM_PARAM_STRING) out->rotate_deg = rot->d; /* JSON reads 30.0 back as an int */
    out->level_count = r == DM_OK ? count : 0;
    for (int k = 0; k < out->level_count && r == DM_OK; ++k) {
        dm_env_level *lv = &out->levels[k];
        char name[DM_PROV_NAME_SIZE];
        int y = 0;
        level_name(name, sizeof name, k, "m");
        r = get_double(p, name, path, &lv->m, err);
        level_name(name, sizeof name, k, "y");
        if (r == DM_OK) r = get_int(p, name, path, 0, img.height - 1, &y, err);
        level_name(name, sizeof name, k, "width");
        if (r == DM_OK) r = get_int(p, name, path, 2, img.width, &lv->width, err);
        lv->height = lv->width / 2;
        double e = -1.0;
        level_name(name, sizeof name, k, "error_rms");
        if (r == DM_OK && get_double(p, name, path, &e, NULL) == DM_OK && e >= 0.0) lv->error.rms_rel = e;
        level_name(name, sizeof name, k, "error_max");
        if (r == DM_OK && get_double(p, name, path, &e, NULL) == DM_OK && e >= 0.0) lv->error.max_rel = e;
        char what[32];
        snprintf(what, sizeof what, "level %d", k);
        if (r == DM_OK) r = copy_rect(&img, planes, lv->width, lv->height, y, what, path, &lv->rgb, err);
    }
    if (r == DM_OK && prov) *prov = img.prov;
    dm_exr_free(&img);
    if (r != DM_OK) dm_env_bake_free(out);
    return r;
}
