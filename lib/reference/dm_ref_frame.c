#include "reference/dm_ref_frame.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mesh/dm_raycast.h"
#include "reference/dm_ref_shade.h"
#include "reference/dm_ref_surface.h"
#include "core/dm_parallel.h"
#include "core/dm_srgb.h"

#define PI 3.14159265358979323846

enum {
    BAND_ROWS = 16, SIZE_MAX_PX = 16384, ATLAS_DEFAULT = DM_REF_FRAME_ATLAS_DEFAULT, ATLAS_MIN = 16, ATLAS_MAX = 8192,
    ATLAS_SAMPLES_DEFAULT = 4, PIXEL_SAMPLES_DEFAULT = 3, SAMPLES_MAX = 8, REFINE_MAX = 16
};

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static double norm3(double v[3])
{
    double l = sqrt(dot3(v, v));
    if (l > 0)
        for (int c = 0; c < 3; ++c) v[c] /= l;
    return l;
}

/* The renderer's camera (dm_render.c frame_camera), in mm. */
typedef struct camera {
    double eye[3], fwd[3], right[3], up[3]; /* right and up scaled by tan(fov/2)(·aspect) */
    double t_near, t_far;                   /* view depth = ray t (fwd component of dir is 1) */
} camera;

static void make_camera(const dm_scene *sc, const dm_raycast *rays, double mm, int width, int height, camera *cam)
{
    double target[3], up_hint[3], s[3], u[3], f[3];
    for (int c = 0; c < 3; ++c) {
        cam->eye[c] = sc->camera_eye[c] * mm;
        target[c] = sc->camera_target[c] * mm;
        up_hint[c] = sc->camera_up[c];
        f[c] = target[c] - cam->eye[c];
    }
    norm3(f);
    cross3(f, up_hint, s);
    if (norm3(s) < 1e-6) { /* up parallel to the view: the renderer's fallback */
        double alt[3] = {fabs(f[0]) < 0.9 ? 1.0 : 0.0, 0.0, fabs(f[0]) < 0.9 ? 0.0 : 1.0};
        cross3(f, alt, s);
        norm3(s);
    }
    cross3(s, f, u);
    double t = tan(0.5 * sc->fov_y_deg * PI / 180.0), aspect = (double)width / height;
    for (int c = 0; c < 3; ++c) {
        cam->fwd[c] = f[c];
        cam->right[c] = s[c] * t * aspect;
        cam->up[c] = u[c] * t;
    }
    double centre[3], rad, d3[3];
    dm_raycast_bounds(rays, centre, &rad);
    if (!(rad > 1e-6 * mm)) rad = mm; /* the renderer's 1-unit radius for a point-sized mesh */
    for (int c = 0; c < 3; ++c) d3[c] = centre[c] - cam->eye[c];
    double d = sqrt(dot3(d3, d3));
    cam->t_near = fmax(d - 2.0 * rad, 0.01 * rad);
    cam->t_far = d + 2.0 * rad;
}

/* The ray through the point (x + fx, y + fy) of the pixel grid (0.5, 0.5: the centre). */
static void pixel_dir_at(const camera *cam, int x, int y, double fx, double fy, int width, int height, double dir[3])
{
    double nx = 2.0 * (x + fx) / width - 1.0, ny = 2.0 * (y + fy) / height - 1.0;
    for (int c = 0; c < 3; ++c) dir[c] = cam->fwd[c] + nx * cam->right[c] + ny * cam->up[c];
}

static void pixel_dir(const camera *cam, int x, int y, int width, int height, double dir[3])
{
    pixel_dir_at(cam, x, y, 0.5, 0.5, width, height, dir);
}

typedef struct frame_job {
    const dm_ref_surface *s;
    const camera *cam;
    int width, height, row0;
    dm_reference_target *hit;  /* per pixel, its centre's ray; triangle −1 on a miss */
    const int64_t *target_of;  /* per pixel: its skin index (index into D), or −1 */
    const float *D;            /* per target, rgb: the skin pixels' centres, then the sub-rays */
    float *rgba;
    int samples;               /* per axis per pixel (k): k² sub-pixel rays when k > 1 */
    dm_reference_target *sub;  /* per skin pixel, its k² sub-pixel rays' hits (k > 1) */
    int64_t *sub_D;            /* per sub-pixel ray: index into D, or −1 (the centre's D) */
    const int64_t *skin_at;    /* per skin index: the pixel */
    float *deviation;             /* per skin index: its rays' mean against its centre ray (may be NULL) */
} frame_job;

static void ray_rows(void *ctx, size_t begin, size_t end)
{
    frame_job *j = ctx;
    for (size_t r = begin; r < end; ++r) {
        int y = j->row0 + (int)r;
        for (int x = 0; x < j->width; ++x) {
            double dir[3];
            pixel_dir(j->cam, x, y, j->width, j->height, dir);
            dm_ray_hit h;
            dm_reference_target *t = &j->hit[(size_t)y * (size_t)j->width + (size_t)x];
            if (dm_raycast_closest(j->s->rays, j->cam->eye, dir, j->cam->t_near, j->cam->t_far, true, &h)) {
                *t = (dm_reference_target){h.triangle, h.b1, h.b2};
            } else {
                *t = (dm_reference_target){-1, 0.0f, 0.0f};
            }
        }
    }
}

static float finite_out(double v)
{
    if (!(v == v)) return 0.0f;
    return (float)(v > 3.0e38 ? 3.0e38 : v < -3.0e38 ? -3.0e38 : v);
}

/* Stage 3b: the k² sub-pixel rays of each skin pixel (rows are skin indices here). */
static void sub_rays(void *ctx, size_t begin, size_t end)
{
    frame_job *j = ctx;
    int k = j->samples;
    for (size_t i = begin; i < end; ++i) {
        size_t at = (size_t)j->skin_at[i];
        int x = (int)(at % (size_t)j->width), y = (int)(at / (size_t)j->width);
        for (int b = 0; b < k; ++b)
            for (int a = 0; a < k; ++a) {
                double dir[3];
                pixel_dir_at(j->cam, x, y, (a + 0.5) / k, (b + 0.5) / k, j->width, j->height, dir);
                dm_ray_hit h;
                dm_reference_target *t = &j->sub[i * (size_t)(k * k) + (size_t)(b * k + a)];
                if (dm_raycast_closest(j->s->rays, j->cam->eye, dir, j->cam->t_near, j->cam->t_far, true, &h))
                    *t = (dm_reference_target){h.triangle, h.b1, h.b2};
                else *t = (dm_reference_target){-1, 0.0f, 0.0f};
            }
    }
}

/* Radiance leaving hit t towards the eye, D the convolved irradiance to use there. */
static void shade_hit(const frame_job *j, const dm_reference_target *t, const float *D, double out[3])
{
    const dm_ref_surface *s = j->s;
    dm_ref_point p;
    dm_ref_surface_point(s, t->triangle, t->b1, t->b2, &p);
    double V[3], diffuse[3], spec[3];
    for (int c = 0; c < 3; ++c) V[c] = j->cam->eye[c] - p.p_mm[c];
    if (!(norm3(V) > 0)) V[0] = 0, V[1] = 0, V[2] = 1;
    if (s->terms.subsurface) {
        for (int c = 0; c < 3; ++c) diffuse[c] = D[c] * pow(p.albedo[c], 1.0 - s->scene.mix);
    } else {
        dm_ref_shade_irradiance(s, &p, diffuse);
        for (int c = 0; c < 3; ++c) diffuse[c] *= p.albedo[c];
    }
    if (s->terms.energy) {
        double ndv = dot3(p.N, V), f = 1.0 - p.rho_s * dm_ref_surface_rho_dt(s, ndv > 0 ? ndv : 0.0, p.m);
        for (int c = 0; c < 3; ++c) diffuse[c] *= f > 0 ? f : 0.0;
    }
    dm_ref_shade_specular(s, &p, V, spec);
    for (int c = 0; c < 3; ++c) out[c] = diffuse[c] + spec[c];
}

/* A pixel: background where its centre's ray misses; else the mean over the samples ×
 * samples sub-pixel rays that hit the head of the radiance there (albedo, normal map,
 * specular: what the renderer's mipmaps filter), each with the convolution D at its own
 * hit — or, with diffusion_at_centre, at the centre's hit (before issue #27: at 320×180 the
 * two differed by 2.5 %). */
static void shade_pixel(const frame_job *j, size_t at, float *o)
{
    const dm_ref_surface *s = j->s;
    const dm_reference_target *t = &j->hit[at];
    int x = (int)(at % (size_t)j->width), y = (int)(at / (size_t)j->width);
    if (t->triangle < 0) {
        double rgb[3] = {0, 0, 0}, dir[3];
        if (s->terms.background) {
            pixel_dir(j->cam, x, y, j->width, j->height, dir);
            norm3(dir);
            dm_ref_shade_env_lookup(s, &s->desc.env_background, dir, rgb);
            for (int c = 0; c < 3; ++c) rgb[c] *= s->scene.env_intensity;
        }
        for (int c = 0; c < 3; ++c) o[c] = finite_out(rgb[c]);
        o[3] = 0.0f;
        return;
    }
    static const float no_D[3] = {0, 0, 0};
    size_t skin = (size_t)j->target_of[at];
    const float *D = s->terms.subsurface ? j->D + skin * 3 : no_D;
    double sum[3] = {0, 0, 0};
    int n = 0, k = j->samples > 1 ? j->samples : 1;
    for (int q = 0; q < k * k && k > 1; ++q) {
        size_t i = skin * (size_t)(k * k) + (size_t)q;
        if (j->sub[i].triangle < 0) continue;
        double rgb[3];
        shade_hit(j, &j->sub[i], s->terms.subsurface && j->sub_D[i] >= 0 ? j->D + (size_t)j->sub_D[i] * 3 : D, rgb);
        for (int c = 0; c < 3; ++c) sum[c] += rgb[c];
        ++n;
    }
    if (n == 0) {
        shade_hit(j, t, D, sum);
        n = 1;
    }
    for (int c = 0; c < 3; ++c) o[c] = finite_out(sum[c] / n);
    if (j->deviation) { /* how far the pixel's mean is from its centre's value: what the rays resolve */
        double centre[3], dev = 0.0;
        shade_hit(j, t, D, centre);
        for (int c = 0; c < 3; ++c)
            if (sum[c] > 0.0) dev = fmax(dev, fabs(sum[c] / n - centre[c]) / (sum[c] / n));
        j->deviation[skin] = (float)fmin(dev, 1e30);
    }
    o[3] = 1.0f;
}

static void shade_rows(void *ctx, size_t begin, size_t end)
{
    frame_job *j = ctx;
    for (size_t r = begin; r < end; ++r) {
        size_t row = (size_t)j->row0 + r;
        for (size_t x = 0; x < (size_t)j->width; ++x) {
            size_t at = row * (size_t)j->width + x;
            shade_pixel(j, at, j->rgba + at * 4);
        }
    }
}

/* Runs fn over the rows in bands, reporting progress after each. */
static void by_bands(frame_job *j, dm_range_fn fn, int thread_count, const dm_ref_frame_options *o,
                     const char *stage)
{
    for (int row0 = 0; row0 < j->height; row0 += BAND_ROWS) {
        int rows = j->height - row0 < BAND_ROWS ? j->height - row0 : BAND_ROWS;
        j->row0 = row0;
        dm_parallel_for((size_t)rows, 1, thread_count, fn, j);
        if (o->progress) o->progress(o->progress_user, stage, (double)(row0 + rows) / j->height);
    }
}

typedef struct stage_progress {
    const dm_ref_frame_options *o;
    const char *stage;
} stage_progress;

static void forward_progress(void *user, double fraction)
{
    stage_progress *p = user;
    if (p->o->progress) p->o->progress(p->o->progress_user, p->stage, fraction);
}

typedef struct frame_state {
    dm_ref_surface *s;
    float *atlas;
    dm_reference *ref;
    dm_reference_target *hit, *targets, *sub;
    int64_t *target_of, *skin_at, *sub_D;
    size_t skin;
    float *D, *deviation;
    stage_progress convolution; /* the reference's progress forwarded under this stage */
} frame_state;

static void free_state(frame_state *st)
{
    dm_reference_destroy(st->ref);
    dm_ref_surface_destroy(st->s);
    free(st->atlas);
    free(st->hit);
    free(st->targets);
    free(st->target_of);
    free(st->sub), free(st->skin_at), free(st->sub_D);
    free(st->D), free(st->deviation);
}

/* The atlas texel as the mean irradiance over its area: k × k sub-texels shaded, those a
 * triangle covers averaged (alpha 1 when any is covered). covered receives the count. */
static void box_down(const float *hi, int size, int k, float *out, int64_t *covered)
{
    size_t W = (size_t)size * (size_t)k;
    *covered = 0;
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            double sum[3] = {0, 0, 0};
            int n = 0;
            for (int b = 0; b < k; ++b)
                for (int a = 0; a < k; ++a) {
                    const float *t = hi + 4 * (((size_t)j * k + (size_t)b) * W + (size_t)i * k + (size_t)a);
                    if (!(t[3] > 0.0f)) continue;
                    for (int c = 0; c < 3; ++c) sum[c] += t[c];
                    ++n;
                }
            float *o = out + 4 * ((size_t)j * (size_t)size + (size_t)i);
            for (int c = 0; c < 3; ++c) o[c] = n ? (float)(sum[c] / n) : 0.0f;
            o[3] = n ? 1.0f : 0.0f;
            *covered += n > 0;
        }
}

int dm_ref_frame_atlas_samples(int atlas_size, int atlas_samples)
{
    int k = atlas_samples ? atlas_samples : ATLAS_SAMPLES_DEFAULT;
    while (k > 1 && atlas_size * k > ATLAS_MAX) --k;
    return k;
}

/* The convolution at n pixels' centres (hit[pixel_of[i]], in that order) and then at their k²
 * sub-pixel rays' hits (sub, k² per pixel; none with at_centre): sub_D receives each sub-ray's
 * index into D (−1: a miss; for odd k the middle ray is the centre's and takes its D).
 * *targets and *D are malloc'd. */
static dm_result diffuse_hits(const dm_reference *ref, const dm_reference_target *hit, const int64_t *pixel_of, size_t n,
                              const dm_reference_target *sub, int k, bool at_centre, int64_t *sub_D,
                              dm_reference_target **targets, float **D, size_t *count, dm_error *err)
{
    size_t kk = k > 1 ? (size_t)k * (size_t)k : 0, subs = at_centre ? 0 : n * kk;
    *targets = malloc((n + subs + 1) * sizeof **targets);
    if (!*targets) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference frame: cannot allocate the targets");
    *count = 0;
    for (size_t i = 0; i < n; ++i) (*targets)[(*count)++] = hit[pixel_of[i]];
    for (size_t i = 0; i < subs; ++i) {
        bool middle = k % 2 == 1 && i % kk == kk / 2;
        sub_D[i] = sub[i].triangle < 0 ? -1 : middle ? (int64_t)(i / kk) : (int64_t)*count;
        if (sub[i].triangle >= 0 && !middle) (*targets)[(*count)++] = sub[i];
    }
    *D = malloc((*count ? *count : 1) * 3 * sizeof **D);
    if (!*D) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference frame: cannot allocate %zu results", *count);
    return *count ? dm_reference_eval(ref, *targets, *count, *D, NULL, err) : DM_OK;
}

/* Stages 2 and 4: the atlas, the convolution at every hit (the skin pixels' centres, then
 * their sub-pixel rays' hits unless o->diffusion_at_centre; for odd k the middle sub-pixel
 * ray is the centre's and takes its D). */
static dm_result diffuse_stage(frame_state *st, const dm_ref_frame_options *o, int atlas_size, int pk,
                               size_t *count, dm_ref_frame_stats *stats, dm_error *err)
{
    size_t n = (size_t)atlas_size * (size_t)atlas_size;
    int k = dm_ref_frame_atlas_samples(atlas_size, o->atlas_samples);
    size_t fine = n * (size_t)k * (size_t)k;
    st->atlas = malloc(n * 4 * sizeof *st->atlas);
    float *hi = k > 1 ? malloc(fine * 4 * sizeof *hi) : st->atlas;
    if (!st->atlas || !hi) {
        if (hi != st->atlas) free(hi);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference frame: cannot allocate the atlas");
    }
    double t0 = now_ms();
    stage_progress sp = {o, "irradiance"};
    dm_ref_atlas_stats as;
    dm_result r = dm_ref_shade_atlas(st->s, atlas_size * k, o->thread_count, hi, &as, forward_progress, &sp, err);
    if (r == DM_OK && k > 1) box_down(hi, atlas_size, k, st->atlas, &as.covered_texels);
    if (hi != st->atlas) free(hi);
    if (r != DM_OK) return r;
    stats->covered_texels = as.covered_texels;
    stats->atlas_ms = now_ms() - t0;
    dm_reference_kernel kernel;
    if (o->kernel) kernel = *o->kernel;
    else if ((r = dm_reference_kernel_from_profile(&st->s->profile, &kernel, err)) != DM_OK) return r;
    dm_reference_options ro = {0};
    if (o->reference) ro = *o->reference;
    ro.thread_count = o->thread_count;
    st->convolution = (stage_progress){o, "convolution"}; /* the reference reports through it, later the refine too */
    ro.progress = forward_progress;
    ro.progress_user = &st->convolution;
    dm_reference_atlas atlas = {atlas_size, atlas_size, st->atlas};
    t0 = now_ms();
    r = dm_reference_create(&st->s->mesh, st->s->mm_per_unit, &atlas, &kernel, &ro, &st->ref, err);
    if (r != DM_OK) return r;
    stats->reference_ms = now_ms() - t0;
    t0 = now_ms();
    r = diffuse_hits(st->ref, st->hit, st->skin_at, st->skin, st->sub, pk, o->diffusion_at_centre, st->sub_D,
                     &st->targets, &st->D, count, err);
    stats->convolution_ms = now_ms() - t0;
    return r;
}

/* Stage 6 (refine_samples): the pixels whose rays' mean leaves the centre (j->deviation) shaded again from
 * K² rays, D at each, in skin order; the rest of the frame stays as stage 5 left it. */
static void shade_list(void *ctx, size_t begin, size_t end)
{
    frame_job *j = ctx;
    for (size_t i = begin; i < end; ++i) shade_pixel(j, (size_t)j->skin_at[i], j->rgba + (size_t)j->skin_at[i] * 4);
}

static dm_result refine_stage(frame_state *st, const frame_job *j, const dm_ref_frame_options *o, size_t npx,
                              dm_ref_frame_stats *stats, dm_error *err)
{
    int K = o->refine_samples;
    size_t R = 0, kk = (size_t)K * (size_t)K;
    for (size_t i = 0; i < st->skin; ++i) R += j->deviation[i] > DM_REF_FRAME_REFINE_DEVIATION;
    int64_t *pix = malloc((R + 1) * sizeof *pix), *map = malloc(npx * sizeof *map), *sub_D = malloc((R * kk + 1) * sizeof *sub_D);
    dm_reference_target *sub = malloc((R * kk + 1) * sizeof *sub), *targets = NULL;
    float *D = NULL;
    dm_result r = pix && map && sub && sub_D ? DM_OK : dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference frame: cannot refine %zu pixels", R);
    if (r == DM_OK) {
        for (size_t at = 0; at < npx; ++at) map[at] = -1;
        for (size_t i = 0, n = 0; i < st->skin; ++i)
            if (j->deviation[i] > DM_REF_FRAME_REFINE_DEVIATION) {
                map[st->skin_at[i]] = (int64_t)n;
                pix[n++] = st->skin_at[i];
            }
        for (size_t i = 0; i < R * kk; ++i) sub_D[i] = -1;
        frame_job j2 = *j;
        j2.samples = K, j2.sub = sub, j2.sub_D = sub_D, j2.skin_at = pix, j2.target_of = map, j2.deviation = NULL;
        double t0 = now_ms();
        dm_parallel_for(R, 16, o->thread_count, sub_rays, &j2);
        stats->rays_ms += now_ms() - t0;
        size_t count = 0;
        t0 = now_ms();
        st->convolution.stage = "refine";
        if (st->s->terms.subsurface)
            r = diffuse_hits(st->ref, st->hit, pix, R, sub, K, o->diffusion_at_centre, sub_D, &targets, &D, &count, err);
        stats->convolution_ms += now_ms() - t0;
        if (r == DM_OK) {
            j2.D = D;
            t0 = now_ms();
            dm_parallel_for(R, 16, o->thread_count, shade_list, &j2);
            stats->compose_ms += now_ms() - t0;
            stats->refined_pixels = (int64_t)R;
        }
    }
    free(pix), free(map), free(sub), free(sub_D), free(targets), free(D);
    return r;
}

dm_result dm_ref_frame_render(const dm_pack *pack, const dm_scene *scene, const dm_ref_frame_options *opt,
                              float *rgba_out, dm_error *err)
{
    assert(pack && scene && rgba_out);
    dm_profile profile;
    dm_ref_surface_desc desc;
    dm_result r = dm_ref_surface_desc_from_pack(pack, scene, &profile, &desc, err);
    return r == DM_OK ? dm_ref_frame_render_desc(&desc, opt, rgba_out, err) : r;
}

dm_result dm_ref_frame_render_desc(const dm_ref_surface_desc *desc, const dm_ref_frame_options *opt,
                                   float *rgba_out, dm_error *err)
{
    assert(desc && desc->scene && rgba_out);
    const dm_scene *scene = desc->scene;
    const dm_ref_frame_options defaults = {0};
    const dm_ref_frame_options *o = opt ? opt : &defaults;
    double t_start = now_ms();
    int width = o->width ? o->width : scene->width, height = o->height ? o->height : scene->height;
    int atlas_size = o->atlas_size ? o->atlas_size : ATLAS_DEFAULT;
    if (width < 1 || height < 1 || width > SIZE_MAX_PX || height > SIZE_MAX_PX)
        return dm_fail(err, DM_ERR_RANGE, "reference frame: size %dx%d, expected 1..%d per side", width, height,
                       SIZE_MAX_PX);
    if (o->pixel_samples < 0 || o->pixel_samples > SAMPLES_MAX || o->atlas_samples < 0 || o->atlas_samples > SAMPLES_MAX)
        return dm_fail(err, DM_ERR_RANGE, "reference frame: %d pixel and %d atlas samples per axis, expected 1..%d",
                       o->pixel_samples, o->atlas_samples, SAMPLES_MAX);
    int pk = o->pixel_samples ? o->pixel_samples : PIXEL_SAMPLES_DEFAULT;
    if (o->refine_samples && (o->refine_samples <= pk || o->refine_samples > REFINE_MAX))
        return dm_fail(err, DM_ERR_RANGE, "reference frame: refine to %d rays per axis, expected more than the %d pixel "
                       "samples and at most %d", o->refine_samples, pk, REFINE_MAX);
    if (atlas_size < ATLAS_MIN || atlas_size > ATLAS_MAX)
        return dm_fail(err, DM_ERR_RANGE, "reference frame: atlas size %d, expected %d..%d", atlas_size, ATLAS_MIN,
                       ATLAS_MAX);
    dm_ref_frame_stats stats = {0};
    frame_state st = {0};
    if (o->progress) o->progress(o->progress_user, "setup", 0.0);
    dm_result r = dm_ref_surface_create(desc, o->thread_count, &st.s, err);
    if (o->progress) o->progress(o->progress_user, "setup", 1.0);
    stats.setup_ms = now_ms() - t_start;
    size_t npx = (size_t)width * (size_t)height;
    if (r == DM_OK) {
        st.hit = malloc(npx * sizeof *st.hit);
        st.target_of = malloc(npx * sizeof *st.target_of);
        if (!st.hit || !st.target_of) r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference frame: out of memory");
    }
    camera cam;
    frame_job j = {0};
    if (r == DM_OK) {
        make_camera(&st.s->scene, st.s->rays, st.s->mm_per_unit, width, height, &cam);
        j = (frame_job){.s = st.s, .cam = &cam, .width = width, .height = height, .hit = st.hit,
                        .target_of = st.target_of, .rgba = rgba_out,
                        .samples = o->pixel_samples ? o->pixel_samples : PIXEL_SAMPLES_DEFAULT};
        double t0 = now_ms();
        by_bands(&j, ray_rows, o->thread_count, o, "rays");
        for (size_t at = 0; at < npx; ++at) st.target_of[at] = st.hit[at].triangle >= 0 ? (int64_t)st.skin++ : -1;
        stats.skin_pixels = (int64_t)st.skin;
        size_t kk = j.samples > 1 ? (size_t)j.samples * (size_t)j.samples : 0;
        st.skin_at = malloc((st.skin + 1) * sizeof *st.skin_at);
        st.sub = malloc((st.skin * kk + 1) * sizeof *st.sub);
        st.sub_D = malloc((st.skin * kk + 1) * sizeof *st.sub_D);
        if (!st.skin_at || !st.sub || !st.sub_D) r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference frame: out of memory");
        for (size_t at = 0; r == DM_OK && at < npx; ++at)
            if (st.target_of[at] >= 0) st.skin_at[st.target_of[at]] = (int64_t)at;
        for (size_t i = 0; r == DM_OK && i < st.skin * kk; ++i) st.sub_D[i] = -1;
        j.sub = st.sub, j.sub_D = st.sub_D, j.skin_at = st.skin_at;
        if (r == DM_OK && kk) dm_parallel_for(st.skin, 64, o->thread_count, sub_rays, &j);
        stats.rays_ms = now_ms() - t0;
    }
    size_t count = 0;
    if (r == DM_OK && st.s->terms.subsurface) r = diffuse_stage(&st, o, atlas_size, j.samples, &count, &stats, err);
    if (r == DM_OK && o->refine_samples && !(st.deviation = malloc((st.skin + 1) * sizeof *st.deviation)))
        r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "reference frame: out of memory");
    if (r == DM_OK) {
        j.D = st.D;
        j.deviation = st.deviation;
        double t0 = now_ms();
        by_bands(&j, shade_rows, o->thread_count, o, "shading");
        stats.compose_ms = now_ms() - t0;
    }
    if (r == DM_OK && o->refine_samples) {
        if (o->progress) o->progress(o->progress_user, "refine", 0.0);
        r = refine_stage(&st, &j, o, npx, &stats, err);
        if (o->progress) o->progress(o->progress_user, "refine", 1.0);
    }
    if (r == DM_OK && o->atlas) {
        *o->atlas = st.atlas;
        st.atlas = NULL;
    }
    free_state(&st);
    stats.total_ms = now_ms() - t_start;
    if (o->stats) *o->stats = stats;
    return r;
}

dm_result dm_ref_frame_hits(const dm_ref_surface *s, int width, int height, int thread_count,
                            dm_reference_target *out, dm_error *err)
{
    assert(s && out);
    if (width < 1 || height < 1 || width > SIZE_MAX_PX || height > SIZE_MAX_PX)
        return dm_fail(err, DM_ERR_RANGE, "reference frame: size %dx%d, expected 1..%d per side", width, height,
                       SIZE_MAX_PX);
    camera cam;
    make_camera(&s->scene, s->rays, s->mm_per_unit, width, height, &cam);
    frame_job j = {.s = s, .cam = &cam, .width = width, .height = height, .hit = out};
    by_bands(&j, ray_rows, thread_count, &(dm_ref_frame_options){0}, "rays");
    return DM_OK;
}

/* ---- display ------------------------------------------------------------------------ */

static double hable(double x)
{
    const double A = 0.15, B = 0.50, C = 0.10, D = 0.20, E = 0.02, F = 0.30;
    return ((x * (A * x + C * B) + D * E) / (x * (A * x + B) + D * F)) - E / F;
}

void dm_ref_frame_display(const dm_scene *scene, const float *rgba, int width, int height, uint8_t *out)
{
    assert(scene && rgba && out);
    const bool tonemap = scene->effects[DM_EFFECT_TONEMAP];
    const double scale = exp2(scene->exposure), white = hable(11.2);
    size_t n = (size_t)width * (size_t)height;
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            double v = rgba[i * 4 + c];
            if (tonemap) {
                v = v * scale;
                v = v > 0 ? (v < 1e30 ? v : 1e30) : 0.0; /* hable(x) → 1/0.15·… as x → ∞: finite */
                v = hable(2.0 * v) / white;
            }
            out[i * 4 + c] = dm_srgb8_from_linear(v);
        }
        out[i * 4 + 3] = 255;
    }
}
