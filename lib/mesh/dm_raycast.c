#include "mesh/dm_raycast.h"

#include <assert.h>
#include <embree3/rtcore.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct dm_raycast {
    RTCDevice device;
    RTCScene scene;
    float *ng;          /* triangle_count × 3: unit front normals (0 for zero-area triangles) */
    int32_t triangle_count;
    double lo[3], hi[3]; /* bounding box, mm */
    double centre[3], radius;
};

/* Embree reports device errors through a callback; the last one is kept for the message. */
static void on_error(void *user, enum RTCError code, const char *str)
{
    char *last = user;
    snprintf(last, 256, "%s (code %d)", str ? str : "unknown", (int)code);
}

dm_result dm_raycast_create(const dm_mesh *mesh, double mm_per_unit, dm_raycast **out, dm_error *err)
{
    assert(mesh && out);
    *out = NULL;
    if (!(mm_per_unit > 0) || !isfinite(mm_per_unit))
        return dm_fail(err, DM_ERR_RANGE, "raycast: mm_per_unit %g, expected a finite value > 0", mm_per_unit);
    dm_raycast *rc = calloc(1, sizeof *rc);
    if (!rc) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "raycast: out of memory");
    char last[256] = "";
    /* one build thread: the BVH, hence the order ties are resolved in, never depends on
     * the machine's core count */
    rc->device = rtcNewDevice("threads=1,set_affinity=0,verbose=0");
    if (!rc->device) {
        free(rc);
        return dm_fail(err, DM_ERR_INTERNAL, "raycast: Embree device creation failed (%d)",
                       (int)rtcGetDeviceError(NULL));
    }
    rtcSetDeviceErrorFunction(rc->device, on_error, last);
    rc->triangle_count = mesh->triangle_count;
    rc->ng = malloc((size_t)mesh->triangle_count * 3 * sizeof *rc->ng);
    RTCGeometry geom = rtcNewGeometry(rc->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = geom ? rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                              (size_t)mesh->vertex_count)
                    : NULL;
    unsigned *ix = geom ? rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                  3 * sizeof(unsigned), (size_t)mesh->triangle_count)
                        : NULL;
    if (!rc->ng || !v || !ix) {
        dm_result code = rc->ng ? DM_ERR_INTERNAL : DM_ERR_OUT_OF_MEMORY;
        if (geom) rtcReleaseGeometry(geom);
        dm_raycast_destroy(rc);
        return dm_fail(err, code, "raycast: cannot allocate %d triangles: %s", (int)mesh->triangle_count, last);
    }
    for (int c = 0; c < 3; ++c) {
        rc->lo[c] = INFINITY;
        rc->hi[c] = -INFINITY;
    }
    for (int32_t i = 0; i < mesh->vertex_count; ++i)
        for (int c = 0; c < 3; ++c) {
            double x = (double)mesh->positions[(size_t)i * 3 + c] * mm_per_unit;
            v[(size_t)i * 3 + c] = (float)x;
            rc->lo[c] = fmin(rc->lo[c], x);
            rc->hi[c] = fmax(rc->hi[c], x);
        }
    double r2 = 0;
    for (int c = 0; c < 3; ++c) rc->centre[c] = 0.5 * (rc->lo[c] + rc->hi[c]);
    for (int32_t i = 0; i < mesh->vertex_count; ++i) {
        double d2 = 0;
        for (int c = 0; c < 3; ++c) {
            double d = (double)mesh->positions[(size_t)i * 3 + c] * mm_per_unit - rc->centre[c];
            d2 += d * d;
        }
        r2 = fmax(r2, d2);
    }
    rc->radius = sqrt(r2);
    for (int32_t t = 0; t < mesh->triangle_count; ++t) {
        const uint32_t *tri = mesh->indices + (size_t)t * 3;
        double p[3][3];
        for (int k = 0; k < 3; ++k) {
            ix[(size_t)t * 3 + k] = tri[k];
            for (int c = 0; c < 3; ++c) p[k][c] = (double)mesh->positions[(size_t)tri[k] * 3 + c] * mm_per_unit;
        }
        double e1[3], e2[3], n[3];
        for (int c = 0; c < 3; ++c) {
            e1[c] = p[1][c] - p[0][c];
            e2[c] = p[2][c] - p[0][c];
        }
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int c = 0; c < 3; ++c) rc->ng[(size_t)t * 3 + c] = l > 0 ? (float)(n[c] / l) : 0.0f;
    }
    rtcCommitGeometry(geom);
    rc->scene = rtcNewScene(rc->device);
    if (rc->scene) {
        rtcSetSceneFlags(rc->scene, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
        rtcSetSceneBuildQuality(rc->scene, RTC_BUILD_QUALITY_HIGH);
        rtcAttachGeometry(rc->scene, geom);
        rtcCommitScene(rc->scene);
    }
    rtcReleaseGeometry(geom);
    enum RTCError e = rtcGetDeviceError(rc->device);
    rtcSetDeviceErrorFunction(rc->device, NULL, NULL);
    if (!rc->scene || e != RTC_ERROR_NONE) {
        dm_raycast_destroy(rc);
        return dm_fail(err, DM_ERR_INTERNAL, "raycast: Embree scene build failed: %s", last[0] ? last : "no message");
    }
    *out = rc;
    return DM_OK;
}

void dm_raycast_destroy(dm_raycast *rc)
{
    if (!rc) return;
    if (rc->scene) rtcReleaseScene(rc->scene);
    if (rc->device) rtcReleaseDevice(rc->device);
    free(rc->ng);
    free(rc);
}

/* The context carries the raycast for the culling filter. */
typedef struct cull_context {
    struct RTCIntersectContext ctx; /* first: Embree hands this pointer back */
    const dm_raycast *rc;
} cull_context;

/* Rejects hits on triangles seen from behind. Embree's SOA layout for N rays: ray field k
 * of ray i at ((float *)ray)[k * N + i] (dir at k = 4, 5, 6), hit primID at
 * ((unsigned *)hit)[5 * N + i] (rtcore_ray.h). */
static void cull_back_faces(const struct RTCFilterFunctionNArguments *a)
{
    const dm_raycast *rc = ((const cull_context *)a->context)->rc;
    const float *ray = (const float *)a->ray;
    const unsigned *hit = (const unsigned *)a->hit;
    const unsigned n = a->N;
    for (unsigned i = 0; i < n; ++i) {
        if (!a->valid[i]) continue;
        unsigned prim = hit[5 * n + i];
        const float *ng = rc->ng + (size_t)prim * 3;
        double d = (double)ray[4 * n + i] * ng[0] + (double)ray[5 * n + i] * ng[1] + (double)ray[6 * n + i] * ng[2];
        if (d >= 0) a->valid[i] = 0;
    }
}

static void set_ray(struct RTCRay *r, const double org[3], const double dir[3], double t_near, double t_far)
{
    r->org_x = (float)org[0];
    r->org_y = (float)org[1];
    r->org_z = (float)org[2];
    r->dir_x = (float)dir[0];
    r->dir_y = (float)dir[1];
    r->dir_z = (float)dir[2];
    r->tnear = (float)t_near;
    r->tfar = t_far < FLT_MAX ? (float)t_far : INFINITY;
    r->time = 0.0f;
    r->mask = 0xFFFFFFFFu;
    r->id = 0;
    r->flags = 0;
}

bool dm_raycast_closest(const dm_raycast *rc, const double org[3], const double dir[3], double t_near,
                        double t_far, bool cull_back, dm_ray_hit *hit)
{
    assert(rc && org && dir && hit);
    cull_context cc;
    rtcInitIntersectContext(&cc.ctx);
    cc.ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    cc.rc = rc;
    if (cull_back) cc.ctx.filter = cull_back_faces;
    struct RTCRayHit rh;
    set_ray(&rh.ray, org, dir, t_near, t_far);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(rc->scene, &cc.ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || rh.hit.primID >= (unsigned)rc->triangle_count) {
        memset(hit, 0, sizeof *hit);
        hit->triangle = -1;
        return false;
    }
    hit->triangle = (int32_t)rh.hit.primID;
    /* clamp into the triangle: Embree's barycentrics can stray by an ulp */
    float b1 = fminf(fmaxf(rh.hit.u, 0.0f), 1.0f), b2 = fminf(fmaxf(rh.hit.v, 0.0f), 1.0f);
    if (b1 + b2 > 1.0f) {
        float s = b1 + b2;
        b1 /= s;
        b2 /= s;
    }
    hit->b1 = b1;
    hit->b2 = b2;
    hit->t = rh.ray.tfar;
    for (int c = 0; c < 3; ++c) hit->ng[c] = rc->ng[(size_t)rh.hit.primID * 3 + c];
    return true;
}

bool dm_raycast_occluded(const dm_raycast *rc, const double org[3], const double dir[3], double t_near,
                         double t_far)
{
    assert(rc && org && dir);
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRay r;
    set_ray(&r, org, dir, t_near, t_far);
    rtcOccluded1(rc->scene, &ctx, &r);
    return r.tfar == -INFINITY; /* Embree marks an occluded ray this way */
}

double dm_raycast_epsilon_mm(const dm_raycast *rc)
{
    double diag2 = 0, big = 0;
    for (int c = 0; c < 3; ++c) {
        double d = rc->hi[c] - rc->lo[c];
        diag2 += d * d;
        big = fmax(big, fmax(fabs(rc->lo[c]), fabs(rc->hi[c])));
    }
    double eps = 1e-5 * sqrt(diag2), ulps = 64.0 * big * FLT_EPSILON;
    return eps > ulps ? eps : ulps > 0 ? ulps : 1e-6;
}

void dm_raycast_bounds(const dm_raycast *rc, double centre_mm[3], double *radius_mm)
{
    for (int c = 0; c < 3; ++c) centre_mm[c] = rc->centre[c];
    *radius_mm = rc->radius;
}
