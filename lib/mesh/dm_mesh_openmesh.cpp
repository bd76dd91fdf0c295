// dm_mesh_openmesh.cpp — the OpenMesh adapter behind dm_mesh_load (dm_mesh.h).
// C++ stays in here. The mesh is read as a PolyMesh with per-halfedge UVs (a halfedge
// carries the UV of the corner it points to) and fan-triangulated by hand, so corner
// UVs survive seams and quads (TOOLCHAIN.md).
#include "mesh/dm_mesh.h"

#include "mesh/dm_isolate.h"
#include "mesh/dm_mesh_gltf.h"
#include "core/dm_input.h"

#include <cassert>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <strings.h>
#include <exception>
#include <string>
#include <vector>


// OpenMesh's VectorT leaves its storage uninitialised by design; GCC 12 then warns
// inside OpenMesh's own property code. The warning is OpenMesh's, not ours.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#pragma GCC diagnostic pop

namespace {

struct Traits : OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3f Point;
    typedef OpenMesh::Vec3f Normal;
    typedef OpenMesh::Vec2f TexCoord2D;
};
typedef OpenMesh::PolyMesh_ArrayKernelT<Traits> PolyMesh;

const char *known_extension(const char *path)
{
    static const char *const exts[] = {"obj", "ply", "off", "stl", "om", "gltf", "glb"};
    const char *dot = std::strrchr(path, '.');
    const char *slash = std::strrchr(path, '/');
    if (!dot || (slash && dot < slash)) return nullptr;
    std::string ext(dot + 1);
    for (char &c : ext) c = (char)std::tolower((unsigned char)c);
    for (const char *e : exts)
        if (ext == e) return e;
    return nullptr;
}

void silence_openmesh()
{
    ::omerr().disable();
    ::omout().disable();
    ::omlog().disable();
}

// Copies the PolyMesh into out, fan-triangulating polygons. Returns DM_OK or a failure.
dm_result convert(const PolyMesh &pm, bool face_uvs, bool vertex_uvs, bool file_normals, const char *path,
                  dm_mesh *out, dm_error *err)
{
    size_t tris = 0;
    for (auto fh : pm.faces()) {
        size_t n = pm.valence(fh);
        if (n >= 3) tris += n - 2;
    }
    if (tris == 0) return dm_fail(err, DM_ERR_EMPTY, "%s: no faces with 3 or more corners", path);
    if (tris > (size_t)DM_MESH_TRIANGLES_MAX)
        return dm_fail(err, DM_ERR_RANGE, "%s: %zu triangles, at most %d supported", path, tris,
                       (int)DM_MESH_TRIANGLES_MAX);
    if (pm.n_vertices() > (size_t)INT32_MAX)
        return dm_fail(err, DM_ERR_RANGE, "%s: %zu vertices, at most %d supported", path, pm.n_vertices(),
                       (int)INT32_MAX);
    dm_result r = dm_mesh_alloc((int32_t)pm.n_vertices(), (int32_t)tris, out, err);
    if (r != DM_OK) return r;
    out->polygon_count = (int64_t)pm.n_faces();
    out->normals_from_file = file_normals ? 1 : 0;
    for (auto vh : pm.vertices()) {
        const auto &p = pm.point(vh);
        for (int k = 0; k < 3; ++k) out->positions[(size_t)vh.idx() * 3 + k] = p[k];
    }
    std::vector<PolyMesh::HalfedgeHandle> ring;
    size_t t = 0;
    for (auto fh : pm.faces()) {
        ring.clear();
        for (auto heh : pm.fh_range(fh)) ring.push_back(heh);
        for (size_t k = 1; k + 1 < ring.size(); ++k) {
            const PolyMesh::HalfedgeHandle corner[3] = {ring[0], ring[k], ring[k + 1]};
            for (int c = 0; c < 3; ++c) {
                auto vh = pm.to_vertex_handle(corner[c]);
                size_t i = t * 3 + (size_t)c;
                out->indices[i] = (uint32_t)vh.idx();
                OpenMesh::Vec2f uv(0.0f, 0.0f);
                if (face_uvs) uv = pm.texcoord2D(corner[c]);
                else if (vertex_uvs) uv = pm.texcoord2D(vh);
                out->uvs[i * 2 + 0] = uv[0];
                out->uvs[i * 2 + 1] = uv[1];
                if (file_normals) {
                    const auto &nrm = pm.normal(vh);
                    for (int d = 0; d < 3; ++d) out->normals[i * 3 + d] = nrm[d];
                }
            }
            ++t;
        }
    }
    assert(t == tris);
    return DM_OK;
}

// Reads and triangulates with OpenMesh in this process.
dm_result read_openmesh(const char *path, const dm_mesh_load_options &o, dm_mesh *out, dm_error *err)
{
    silence_openmesh();
    try {
        PolyMesh pm;
        pm.request_vertex_normals();
        pm.request_vertex_texcoords2D();
        pm.request_halfedge_texcoords2D();
        OpenMesh::IO::Options ropt;
        ropt += OpenMesh::IO::Options::FaceTexCoord;
        ropt += OpenMesh::IO::Options::VertexTexCoord;
        ropt += OpenMesh::IO::Options::VertexNormal;
        if (!OpenMesh::IO::read_mesh(pm, path, ropt))
            return dm_fail(err, DM_ERR_FORMAT, "%s: the reader refused the file (malformed, or a face index out of range)",
                           path);
        if (pm.n_faces() == 0) {
            if (pm.n_vertices() > 0)
                return dm_fail(err, DM_ERR_EMPTY,
                               "%s: %zu vertices but no faces (points or lines only, or every face refused: "
                               "index out of range, repeated corner), expected triangles or polygons",
                               path, pm.n_vertices());
            return dm_fail(err, DM_ERR_EMPTY, "%s: no vertices and no faces, expected a mesh", path);
        }
        // STL has no texture coordinates, but OpenMesh's STL reader leaves the requested
        // texcoord options set (the UVs then read as NaN): decide by the format.
        const size_t len = std::strlen(path);
        const bool stl = len >= 4 && strcasecmp(path + len - 4, ".stl") == 0;
        const bool face_uvs = !stl && ropt.face_has_texcoord();
        const bool vertex_uvs = !stl && !face_uvs && ropt.vertex_has_texcoord();
        if (!face_uvs && !vertex_uvs && !o.uvs_optional)
            return dm_fail(err, DM_ERR_FORMAT,
                           "%s: no texture coordinates%s, expected a UV layout (texture-space diffusion needs one): "
                           "export the mesh with its UVs as OBJ (vt), PLY or glTF (TEXCOORD_0)",
                           path, stl ? " (STL cannot hold them)" : "");
        const bool file_normals = ropt.vertex_has_normal() && !o.ignore_file_normals;
        return convert(pm, face_uvs, vertex_uvs, file_normals, path, out, err);
    } catch (const std::bad_alloc &) {
        dm_mesh_free(out);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory while reading", path);
    } catch (const std::exception &e) {
        dm_mesh_free(out);
        return dm_fail(err, DM_ERR_FORMAT, "%s: the reader failed (%s)", path, e.what());
    }
}

// ---- isolation: OpenMesh's binary readers trust their input (a mutated OM, PLY or OFF
// file can crash them, trip their asserts or loop forever), and so may tinygltf, so by
// default the reader runs in a child process (dm_isolate.h) that sends the finished
// mesh back through a pipe.

typedef dm_result (*mesh_reader)(const char *path, const dm_mesh_load_options *o, dm_mesh *out, dm_error *err);

struct wire_header {
    int32_t vertex_count, triangle_count, normals_from_file, has_tangents;
    int64_t polygon_count;
};

struct isolated_read {
    const char *path;
    const dm_mesh_load_options *o;
    mesh_reader read;
    dm_mesh *out;
};

void child_read(void *ctx, int fd)
{
    const isolated_read &c = *static_cast<const isolated_read *>(ctx);
    dm_mesh m;
    std::memset(&m, 0, sizeof m);
    dm_error e = {};
    dm_result r = c.read(c.path, c.o, &m, &e);
    if (!dm_isolate_write_result(fd, r, &e) || r != DM_OK) return;
    wire_header h = {m.vertex_count, m.triangle_count, m.normals_from_file, m.tangents != nullptr, m.polygon_count};
    const size_t corners = (size_t)m.triangle_count * 3;
    dm_isolate_write(fd, &h, sizeof h) &&
        dm_isolate_write(fd, m.positions, (size_t)m.vertex_count * 3 * sizeof(float)) &&
        dm_isolate_write(fd, m.indices, corners * sizeof(uint32_t)) &&
        dm_isolate_write(fd, m.uvs, corners * 2 * sizeof(float)) &&
        dm_isolate_write(fd, m.normals, corners * 3 * sizeof(float)) &&
        (!m.tangents || dm_isolate_write(fd, m.tangents, corners * 4 * sizeof(float)));
}

dm_result parent_read(void *ctx, dm_isolate_pipe *pp, dm_error *err)
{
    const isolated_read &c = *static_cast<const isolated_read *>(ctx);
    dm_mesh *out = c.out;
    dm_result r = DM_OK;
    if (!dm_isolate_read_result(pp, &r, err) || r != DM_OK) return r;
    wire_header h;
    if (!dm_isolate_read(pp, &h, sizeof h)) return DM_ERR_FORMAT;
    if ((r = dm_mesh_alloc(h.vertex_count, h.triangle_count, out, err)) != DM_OK) return r;
    out->normals_from_file = h.normals_from_file, out->polygon_count = h.polygon_count;
    const size_t corners = (size_t)h.triangle_count * 3;
    if (h.has_tangents && !(out->tangents = static_cast<float *>(std::malloc(corners * 4 * sizeof(float))))) {
        dm_mesh_free(out);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", c.path);
    }
    if (!dm_isolate_read(pp, out->positions, (size_t)h.vertex_count * 3 * sizeof(float)) ||
        !dm_isolate_read(pp, out->indices, corners * sizeof(uint32_t)) ||
        !dm_isolate_read(pp, out->uvs, corners * 2 * sizeof(float)) ||
        !dm_isolate_read(pp, out->normals, corners * 3 * sizeof(float)) ||
        (h.has_tangents && !dm_isolate_read(pp, out->tangents, corners * 4 * sizeof(float)))) {
        dm_mesh_free(out);
        return DM_ERR_FORMAT;
    }
    return DM_OK;
}

dm_result read_isolated(const char *path, const dm_mesh_load_options *o, mesh_reader read, dm_mesh *out,
                        dm_error *err)
{
    isolated_read c = {path, o, read, out};
    return dm_isolate_run(path, dm_isolate_limit_ms(path), child_read, parent_read, &c, err);
}

dm_result read_openmesh_c(const char *path, const dm_mesh_load_options *o, dm_mesh *out, dm_error *err)
{
    return read_openmesh(path, *o, out, err);
}

} // namespace

extern "C" dm_result dm_mesh_load(const char *path, const dm_mesh_load_options *opt, dm_mesh *out, dm_error *err)
{
    assert(path && out);
    std::memset(out, 0, sizeof *out);
    dm_mesh_load_options o = {};
    if (opt) o = *opt;

    if (!known_extension(path))
        return dm_fail(err, DM_ERR_UNSUPPORTED,
                       "%s: unknown mesh format, expected .obj, .ply, .off, .stl, .om, .gltf or .glb", path);
    // The input rules here, in this process: the reader's child must not get a FIFO (whose
    // open would hang until its time limit) or /dev/zero (read until memory runs out).
    uint64_t size = 0;
    dm_result r = dm_input_check(path, DM_INPUT_MESH, &size, err);
    if (r != DM_OK) return r;
    if (size == 0) return dm_fail(err, DM_ERR_EMPTY, "%s: the file is empty, expected a mesh", path);

    if ((r = dm_mesh_check_file(path, err)) != DM_OK) return r;
    const mesh_reader read = dm_mesh_is_gltf(path) ? dm_mesh_read_gltf : read_openmesh_c;
    r = o.in_process ? read(path, &o, out, err) : read_isolated(path, &o, read, out, err);
    if (r == DM_OK) {
        // Positions and UVs first: normals are only checked after they are final.
        for (int64_t i = 0; i < (int64_t)out->vertex_count * 3 && r == DM_OK; ++i)
            if (!std::isfinite(out->positions[i]))
                r = dm_fail(err, DM_ERR_NON_FINITE, "%s: vertex %lld has a non-finite coordinate (%g), expected finite numbers",
                            path, (long long)(i / 3 + 1), (double)out->positions[i]);
        for (int64_t i = 0; i < (int64_t)out->triangle_count * 6 && r == DM_OK; ++i)
            if (!std::isfinite(out->uvs[i]))
                r = dm_fail(err, DM_ERR_NON_FINITE, "%s: triangle %lld has a non-finite UV (%g), expected finite numbers",
                            path, (long long)(i / 6), (double)out->uvs[i]);
    }
    if (r == DM_OK && !out->normals_from_file) dm_mesh_compute_normals(out);
    if (r == DM_OK && out->normals_from_file) {
        for (int64_t i = 0; i < (int64_t)out->triangle_count * 9 && r == DM_OK; ++i)
            if (!std::isfinite(out->normals[i]))
                r = dm_fail(err, DM_ERR_NON_FINITE, "%s: vertex %u has a non-finite normal (%g), expected finite numbers",
                            path, out->indices[i / 3] + 1, (double)out->normals[i]);
        // A zero-length file normal (common in exported files) makes the whole mesh's
        // normals computed instead: normals do not decide stretch, tangents need them.
        bool zero = false;
        for (int64_t i = 0; i < (int64_t)out->triangle_count * 3 && r == DM_OK && !zero; ++i) {
            const float *n = out->normals + i * 3;
            zero = (double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2] < 1e-12;
        }
        if (r == DM_OK && zero) {
            out->normals_from_file = 0;
            std::free(out->tangents); // they went with the file's normals
            out->tangents = nullptr;
            dm_mesh_compute_normals(out);
        } else if (r == DM_OK) {
            for (int64_t i = 0; i < (int64_t)out->triangle_count * 3; ++i) {
                float *n = out->normals + i * 3;
                double len = std::sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
                for (int d = 0; d < 3; ++d) n[d] = (float)(n[d] / len);
            }
        }
    }
    if (r == DM_OK) r = dm_mesh_validate(out, path, err);
    if (r != DM_OK) dm_mesh_free(out);
    return r;
}
