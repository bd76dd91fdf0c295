/* dm_mesh.h — triangle meshes with per-corner UVs and normals, as plain C arrays.
 *
 * A dm_mesh is what the offline side works on: positions shared by index, and per
 * corner (three per triangle) a UV and a normal, so UV seams and hard edges survive
 * loading. Loading goes through OpenMesh (dm_mesh_openmesh.cpp, C++ behind this
 * header) for OBJ, PLY, OFF, STL and OM, and through tinygltf (dm_mesh_gltf.cpp) for
 * glTF 2.0 (.gltf, .glb), chosen by the file extension. Polygons are read as polygons
 * and fan-triangulated here, each new triangle keeping its corners' UVs (OpenMesh's own
 * triangulate() loses them on the new diagonals).
 *
 * glTF: every triangle primitive of every mesh the default scene places (or of every
 * mesh, when the file has no scene) is merged, node transforms applied (a negative
 * determinant flips the winding); dm_mesh_load_options.mesh_name keeps only the meshes
 * of that name. TEXCOORD_0 is flipped to this convention (v = 1 − v_glTF); NORMAL and
 * TANGENT are kept when given; indices may be u8, u16 or u32; buffers may be the GLB's
 * own, data URIs or files in the .gltf's folder and below (core/dm_uri.h: an absolute
 * URI, a ".." or one that leaves the folder refuses the file, DM_ERR_FILE_OPEN). Vertices glTF split at UV seams are
 * welded back by bit-identical position, so computed normals are smooth across seams
 * and the mesh has the same shape as the OBJ of the same head. Refused, naming the
 * file and the place: sparse accessors, KHR_draco_mesh_compression and
 * EXT_meshopt_compression (DM_ERR_UNSUPPORTED), triangle strips and fans
 * (DM_ERR_UNSUPPORTED), accessors or buffer views out of their buffer, wrong types
 * (DM_ERR_FORMAT), indices out of range (DM_ERR_RANGE), no TEXCOORD_0 (DM_ERR_FORMAT).
 *
 * Units are the file's ("mesh units"); callers scale to mm with the scene's
 * mm_per_unit. UVs follow OBJ/OpenGL: v = 0 is the bottom row of an image.
 *
 * Ownership: every array of a dm_mesh or dm_gpu_mesh is malloc'd by the function that
 * fills the struct and freed by dm_mesh_free / dm_gpu_mesh_free (safe on a zeroed or
 * already-freed struct, and after a failure).
 */
#ifndef DM_MESH_H
#define DM_MESH_H

#include <stdint.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_MESH_TRIANGLES_MAX = 1 << 28 }; /* keeps every corner index in int32 range */

typedef struct dm_mesh {
    int32_t vertex_count;
    float *positions;       /* vertex_count * 3 (x, y, z), mesh units */
    int32_t triangle_count;
    uint32_t *indices;      /* triangle_count * 3 position indices, counter-clockwise
                             * seen from the side the normals point to */
    float *uvs;             /* triangle_count * 3 * 2: corner c of triangle t at
                             * uvs[(3 t + c) * 2] */
    float *normals;         /* triangle_count * 3 * 3, unit length, per corner */
    float *tangents;        /* NULL, or triangle_count * 3 * 4 per corner (x, y, z, w = ±1)
                             * when the file gave them (glTF TANGENT) with its normals;
                             * dm_mesh_alloc leaves it NULL, dm_mesh_free frees it */
    int normals_from_file;  /* 1: the file's (vertex) normals; 0: computed (area-weighted) */
    int64_t polygon_count;  /* faces in the file before triangulation (0 when built in code) */
} dm_mesh;

typedef struct dm_mesh_load_options {
    int uvs_optional;          /* 0 (default): a file without texture coordinates is an
                                * error; 1: allowed, every UV is (0, 0) */
    int ignore_file_normals;   /* 1: compute normals even when the file has them */
    int in_process;            /* 1: run OpenMesh's reader in this process (faster start,
                                * for debugging); 0 (default): in a child process, so a
                                * reader crash or hang on a malformed file becomes an
                                * error (see dm_mesh_load) */
    const char *mesh_name;     /* glTF only: NULL or "" (default) merges every mesh; else
                                * only the meshes of this name (DM_ERR_MISMATCH, listing
                                * the names, when none has it). Ignored by other formats. */
} dm_mesh_load_options;

/* Loads a mesh (opt may be NULL for defaults). Fails, naming the file and the problem,
 * with DM_ERR_FILE_OPEN (missing or unreadable), DM_ERR_UNSUPPORTED (unknown
 * extension), DM_ERR_FORMAT (the reader refused it, no texture coordinates), DM_ERR_EMPTY
 * (no faces, or points/lines only), DM_ERR_NON_FINITE (NaN/Inf in a position, UV or
 * normal), DM_ERR_RANGE (too many triangles). Faces OpenMesh drops (non-manifold,
 * duplicate) are lost; polygon_count says how many were kept. OpenMesh's own messages
 * are silenced: its global streams omerr/omout/omlog are disabled by this call.
 * OpenMesh's readers trust their input (a mutated OM, PLY or OFF file can crash them,
 * trip their asserts or loop forever), so by default the read runs in a forked child
 * that sends the mesh back through a pipe: a crash becomes DM_ERR_FORMAT "the reader
 * crashed on this file", a hang (30 s + 1 s per MB) the same after killing the child.
 * tinygltf runs in the child the same way. The file itself is checked here first under
 * core/dm_input.h's rules (a regular file under the mesh cap), so a FIFO or a device never
 * reaches the child. File normals are made unit length; a
 * zero-length one makes every normal computed (and file tangents dropped).
 * Fork from a point where no other thread holds a lock (tools load before they start
 * worker threads). Free with dm_mesh_free, also after a failure. */
dm_result dm_mesh_load(const char *path, const dm_mesh_load_options *opt, dm_mesh *out, dm_error *err);

/* Checks what OpenMesh's readers trust, before they read (dm_mesh_load calls it):
 *  .obj: text only (a NUL or other control character but tab and CR is DM_ERR_FORMAT:
 *        OpenMesh would read what this check did not), every v/vt/vn line has its
 *        numbers, finite as floats (else DM_ERR_NON_FINITE or DM_ERR_FORMAT), every face corner's v/vt/vn index is non-zero and refers to an
 *        element already defined (DM_ERR_RANGE; negative indices count back), every
 *        face has 3 or more corners (DM_ERR_FORMAT): an index out of range is an
 *        out-of-bounds access inside OpenMesh. Messages are "FILE:LINE: ...".
 *  .ply: the header starts with "ply" and ends with an "end_header" line within its
 *        first 64 KiB (DM_ERR_FORMAT): OpenMesh's PLY probe loops forever otherwise.
 * Other formats pass unchecked. */
dm_result dm_mesh_check_file(const char *path, dm_error *err);

/* Allocates a mesh with zeroed arrays for the caller to fill (tests, generators).
 * vertex_count ≥ 1, triangle_count in [1, DM_MESH_TRIANGLES_MAX]. */
dm_result dm_mesh_alloc(int32_t vertex_count, int32_t triangle_count, dm_mesh *out, dm_error *err);
void dm_mesh_free(dm_mesh *m);

/* Checks that every index is < vertex_count and that positions, UVs and normals are
 * finite; `what` (usually the file name) prefixes the message, which names the first
 * offending triangle or vertex and its value. */
dm_result dm_mesh_validate(const dm_mesh *m, const char *what, dm_error *err);

/* Writes area-weighted, smooth per-vertex normals into every corner (shared by position
 * index). A vertex whose triangles all have zero area gets (0, 0, 1). Never NaN. */
void dm_mesh_compute_normals(dm_mesh *m);

/* 1-to-4 midpoint subdivision (flat: new positions, UVs and normals are edge midpoints,
 * normals renormalised). Midpoint vertices are shared between the two triangles of an
 * edge. The surface and its UV map are unchanged, so stretch is unchanged; used to
 * make large test meshes. triangle_count × 4 must stay ≤ DM_MESH_TRIANGLES_MAX.
 * File tangents are not carried over (out->tangents is NULL). */
dm_result dm_mesh_subdivide(const dm_mesh *m, dm_mesh *out, dm_error *err);

/* The UV Jacobian of a triangle: the one copy the stretch bake and the tangent frames
 * use, with one test for degenerate triangles. With D = det [uv1 − uv0, uv2 − uv0] and
 * the edges e1, e2 (positions × scale), a = e1 dv2 − e2 dv1 = D ∂P/∂u and
 * b = e2 du1 − e1 du2 = D ∂P/∂v. "Zero" is relative: |D| ≤ 1e-9 of the squared UV edge
 * lengths is DM_TRIANGLE_ZERO_UV_AREA; |e1 × e2| ≤ 1e-9 of the squared edge lengths, or
 * an |∂P/∂u| or |∂P/∂v| whose inverse overflows a float, is DM_TRIANGLE_ZERO_AREA (an
 * angle of about 1e-9 rad between the edges, far below anything a float mesh means as a
 * face). Fields past kind are valid when kind is DM_TRIANGLE_OK. */
typedef enum dm_triangle_kind {
    DM_TRIANGLE_OK = 0,
    DM_TRIANGLE_ZERO_UV_AREA,
    DM_TRIANGLE_ZERO_AREA
} dm_triangle_kind;
typedef struct dm_uv_jacobian {
    dm_triangle_kind kind;
    double det;        /* D, UV units²; < 0: the UV map is mirrored here */
    double a[3], b[3]; /* D ∂P/∂u, D ∂P/∂v (position units × scale × UV units) */
    double la, lb;     /* |a|, |b| */
} dm_uv_jacobian;
void dm_mesh_uv_jacobian(const dm_mesh *m, int32_t t, double scale, dm_uv_jacobian *out);

/* Surface area of a triangle and its signed UV area (positive: counter-clockwise in UV,
 * the same turn as the triangle in 3-D; negative: mirrored UVs). Double precision. */
double dm_mesh_triangle_area(const dm_mesh *m, int32_t t);
double dm_mesh_triangle_uv_area(const dm_mesh *m, int32_t t);

/* Counts UV islands: triangles connected through shared corners (same position index
 * and bit-identical UV). island_of (may be NULL) receives triangle_count island numbers,
 * numbered in order of first triangle. m must be valid. */
dm_result dm_mesh_uv_islands(const dm_mesh *m, int32_t *island_of, int32_t *island_count, dm_error *err);

/* ---- GPU-ready mesh --------------------------------------------------------------- */

/* Vertices split by (position, uv, normal, UV handedness): planar float arrays and
 * uint32 triangle indices, the form the pack uploads as-is. Tangent frames follow the
 * glTF / MikkTSpace convention: tangents[4 i .. 4 i + 2] is the unit tangent along +u,
 * orthogonal to the normal; tangents[4 i + 3] = w = ±1, and the bitangent (along +v)
 * is w · cross(normal, tangent). w = −1 on mirrored UVs; because handedness is part of
 * the split key, a vertex never mixes mirrored and unmirrored triangles. Vertices whose
 * triangles have no UV area get any unit tangent orthogonal to the normal and w = +1.
 * When the mesh has file tangents (dm_mesh.tangents), each vertex takes the one of its
 * first corner instead, made orthogonal to the normal, with its w (a degenerate one
 * falls back to the computed frame). */
typedef struct dm_gpu_mesh {
    int32_t vertex_count;
    float *positions;  /* vertex_count * 3 */
    float *normals;    /* vertex_count * 3, unit */
    float *uvs;        /* vertex_count * 2 */
    float *tangents;   /* vertex_count * 4 (x, y, z, w) */
    int32_t index_count; /* 3 × triangles */
    uint32_t *indices;   /* index_count, counter-clockwise */
} dm_gpu_mesh;

/* Splits m for the GPU (m must be valid: dm_mesh_validate). Vertices are numbered in
 * order of first use, so the result is deterministic. Free with dm_gpu_mesh_free. */
dm_result dm_mesh_split_for_gpu(const dm_mesh *m, dm_gpu_mesh *out, dm_error *err);
void dm_gpu_mesh_free(dm_gpu_mesh *g);

#ifdef __cplusplus
}
#endif
#endif
