/* dm_uv_raster.h — rasterizing a mesh's triangles in UV space: which triangle covers
 * each texel.
 *
 * Texel (i, j) of a width × height texture is covered by a triangle when its centre
 * ((i + 0.5)/width, (j + 0.5)/height) lies inside the triangle's UV image. Rows are
 * bottom-up (row 0 is v ≈ 0). Corners are snapped to 1/256 texel and tested with exact
 * integer edge functions; a centre exactly on an edge belongs to the triangle for which
 * that edge is a "left" edge, or a "bottom" one when horizontal (the top-left rule
 * turned for y up), so an edge shared by two triangles covers its texels once, and a
 * mirrored triangle is tested like any other (its orientation is flipped first).
 * Triangles of zero UV area cover nothing. UVs outside [0, 1] are clipped, not
 * wrapped; a triangle with a corner beyond ±2^20 texels is skipped and counted.
 * Where charts overlap, the triangle of lowest index keeps the texel and the others
 * are counted as overlaps. Results do not depend on the thread count.
 */
#ifndef DM_UV_RASTER_H
#define DM_UV_RASTER_H

#include <stdint.h>

#include "mesh/dm_mesh.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_UV_RASTER_SIZE_MAX = 16384, DM_UV_RASTER_SUBTEXEL = 256 };

typedef struct dm_uv_raster_stats {
    int64_t covered_texels;   /* texels with a triangle */
    int64_t overlap_texels;   /* extra claims on already covered texels (UV overlaps) */
    int64_t zero_area_triangles;    /* zero UV area after snapping: cover nothing */
    int64_t out_of_range_triangles; /* a corner beyond ±2^20 texels: skipped */
} dm_uv_raster_stats;

/* Fills triangle_of[j * width + i] (width*height int32, caller-owned) with the index of
 * the covering triangle or −1. m must be valid (dm_mesh_validate). skip (may be NULL):
 * triangle_count flags, non-zero = leave that triangle out. Sizes in
 * [1, DM_UV_RASTER_SIZE_MAX]; thread_count 0 = all cores. stats may be NULL. Allocates
 * about 32 bytes per triangle of scratch for the call. */
dm_result dm_uv_raster(const dm_mesh *m, const uint8_t *skip, int width, int height, int thread_count,
                       int32_t *triangle_of, dm_uv_raster_stats *stats, dm_error *err);

/* The barycentrics of the UV point (u, v) in triangle t's UV image: *b1, *b2 those of corners
 * 1 and 2 (corner 0 gets 1 − b1 − b2), clamped into the triangle, since a covered texel's
 * centre is inside only up to the 1/256-texel snapping. Signed, so mirrored UVs work alike.
 * t must have UV area (dm_uv_raster covers texels only with such triangles). */
void dm_uv_raster_barycentrics(const dm_mesh *m, int32_t t, double u, double v, double *b1, double *b2);

#ifdef __cplusplus
}
#endif
#endif
