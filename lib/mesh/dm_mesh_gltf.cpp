// dm_mesh_gltf.cpp — the tinygltf adapter behind dm_mesh_load (dm_mesh.h, dm_mesh_gltf.h).
// C++ stays in here. tinygltf parses the JSON and resolves buffers (GLB chunk, data
// URIs, files in the .gltf's folder and below only: core/dm_uri.h, through the file
// callbacks below); everything it does not check — accessor and buffer view
// ranges, component types, index ranges, node cycles — is checked here before a byte is
// read, so a malformed file is an error naming the file and the place.
#include "mesh/dm_mesh_gltf.h"

#include "core/dm_input.h"
#include "core/dm_uri.h"

#include <array>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include <unistd.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <tiny_gltf.h>
#pragma GCC diagnostic pop

namespace {

bool ends_with_ci(const char *s, const char *suffix)
{
    size_t n = std::strlen(s), k = std::strlen(suffix);
    if (n < k) return false;
    for (size_t i = 0; i < k; ++i)
        if (std::tolower((unsigned char)s[n - k + i]) != suffix[i]) return false;
    return true;
}

// Image bytes are not decoded here: kept as they are (for dm_gltf_map) or dropped.
bool keep_image(tinygltf::Image *img, const int, std::string *, std::string *, int, int, const unsigned char *bytes,
                int size, void *user)
{
    if (user && bytes && size > 0) {
        img->image.assign(bytes, bytes + size);
        img->as_is = true;
    }
    return true;
}

dm_result check_glb_header(const char *path, dm_error *err)
{
    int fd = -1;
    dm_result r = dm_input_open(path, DM_INPUT_MESH, &fd, nullptr, err);
    if (r != DM_OK) return r;
    FILE *f = fdopen(fd, "rb");
    if (!f) {
        close(fd);
        return dm_fail(err, DM_ERR_FILE_OPEN, "%s: cannot open (%s)", path, std::strerror(errno));
    }
    unsigned char h[12];
    size_t got = std::fread(h, 1, sizeof h, f);
    std::fseek(f, 0, SEEK_END);
    long size = std::ftell(f);
    std::fclose(f);
    if (got < 12) return dm_fail(err, DM_ERR_FORMAT, "%s: %zu bytes, a GLB has a 12-byte header: truncated", path, got);
    uint32_t magic = h[0] | h[1] << 8 | h[2] << 16 | (uint32_t)h[3] << 24;
    uint32_t version = h[4] | h[5] << 8 | h[6] << 16 | (uint32_t)h[7] << 24;
    uint32_t length = h[8] | h[9] << 8 | h[10] << 16 | (uint32_t)h[11] << 24;
    if (magic != 0x46546C67u) return dm_fail(err, DM_ERR_FORMAT, "%s: does not start with \"glTF\", expected a GLB", path);
    if (version != 2) return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: GLB version %u, expected 2", path, version);
    if ((long)length > size)
        return dm_fail(err, DM_ERR_FORMAT, "%s: the header says %u bytes, the file has %ld: truncated", path, length,
                       size);
    return DM_OK;
}

// tinygltf reads a buffer's or an image's file through these callbacks, so the glTF's
// URIs follow dermis's rules (core/dm_uri.h, core/dm_input.h): inside the glTF's folder,
// regular files under a cap. tinygltf looks a URI up as JoinPath(base, uri), then as
// JoinPath(".", uri) (the current folder), which is never allowed. The first refusal is
// kept: tinygltf only warns about an image it cannot read, and its own message for a
// buffer would be "File not found".
struct fs_guard {
    std::string gltf, prefix; // the file, and its folder with a trailing '/'
    std::string refusal;      // the first refusal's message
    std::string fallback;     // the current-folder lookup that follows a failed one
};

bool fs_exists(const std::string &abs, void *user)
{
    fs_guard &g = *static_cast<fs_guard *>(user);
    if (!g.fallback.empty() && abs == g.fallback) {
        g.fallback.clear();
        return false;
    }
    if (abs.compare(0, g.prefix.size(), g.prefix) != 0) return false;
    const std::string uri = abs.substr(g.prefix.size());
    std::vector<char> out(8192);
    bool missing = false;
    dm_error e = {};
    dm_result r = dm_uri_resolve(g.gltf.c_str(), uri.c_str(), false, out.data(), out.size(), &missing, &e);
    if (r == DM_OK) r = dm_input_check(out.data(), DM_INPUT_MESH, nullptr, &e);
    if (r == DM_OK) return true;
    if (!missing && g.refusal.empty()) g.refusal = e.detail;
    g.fallback = "./" + uri;
    return false;
}

std::string fs_expand(const std::string &path, void *) { return path; } // no ~, no $VAR

bool fs_read(std::vector<unsigned char> *out, std::string *msg, const std::string &path, void *user)
{
    fs_guard &g = *static_cast<fs_guard *>(user);
    char *data = nullptr;
    size_t size = 0;
    dm_error e = {};
    if (dm_input_read(path.c_str(), DM_INPUT_MESH, &data, &size, &e) != DM_OK) {
        if (g.refusal.empty()) g.refusal = e.detail;
        if (msg) *msg = e.detail;
        return false;
    }
    out->assign(data, data + size);
    std::free(data);
    return true;
}

bool fs_write(std::string *msg, const std::string &, const std::vector<unsigned char> &, void *)
{
    if (msg) *msg = "dermis writes no glTF";
    return false;
}

std::string one_line(std::string s)
{
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    for (char &c : s)
        if (c == '\n') c = ' ';
    if (s.size() > 300) s = s.substr(0, 300) + "...";
    return s;
}

void mat_mul(const double a[16], const double b[16], double out[16])
{
    double r[16];
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) {
            double s = 0.0;
            for (int k = 0; k < 4; ++k) s += a[k * 4 + row] * b[c * 4 + k];
            r[c * 4 + row] = s;
        }
    std::memcpy(out, r, sizeof r);
}

const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

dm_result local_matrix(const char *path, const tinygltf::Node &n, int index, double m[16], dm_error *err)
{
    if (!n.matrix.empty()) {
        if (n.matrix.size() != 16)
            return dm_fail(err, DM_ERR_FORMAT, "%s: nodes[%d].matrix has %zu numbers, expected 16", path, index,
                           n.matrix.size());
        for (int k = 0; k < 16; ++k) m[k] = n.matrix[(size_t)k];
    } else {
        if ((!n.translation.empty() && n.translation.size() != 3) || (!n.rotation.empty() && n.rotation.size() != 4) ||
            (!n.scale.empty() && n.scale.size() != 3))
            return dm_fail(err, DM_ERR_FORMAT,
                           "%s: nodes[%d]: translation/rotation/scale of %zu/%zu/%zu numbers, expected 3/4/3", path,
                           index, n.translation.size(), n.rotation.size(), n.scale.size());
        double t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
        for (size_t k = 0; k < n.translation.size(); ++k) t[k] = n.translation[k];
        for (size_t k = 0; k < n.rotation.size(); ++k) q[k] = n.rotation[k];
        for (size_t k = 0; k < n.scale.size(); ++k) s[k] = n.scale[k];
        const double x = q[0], y = q[1], z = q[2], w = q[3];
        const double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
                             2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                             2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)}; // columns
        for (int c = 0; c < 3; ++c) {
            for (int row = 0; row < 3; ++row) m[c * 4 + row] = r[c * 3 + row] * s[c];
            m[c * 4 + 3] = 0.0;
        }
        m[12] = t[0], m[13] = t[1], m[14] = t[2], m[15] = 1.0;
    }
    for (int k = 0; k < 16; ++k)
        if (!std::isfinite(m[k]))
            return dm_fail(err, DM_ERR_NON_FINITE, "%s: nodes[%d] has a non-finite transform (%g)", path, index, m[k]);
    return DM_OK;
}

dm_result visit(const char *path, const tinygltf::Model &model, int node, const double parent[16], size_t depth,
                std::vector<dm_gltf::instance> *out, dm_error *err)
{
    if (node < 0 || (size_t)node >= model.nodes.size())
        return dm_fail(err, DM_ERR_FORMAT, "%s: node index %d, expected < %zu", path, node, model.nodes.size());
    if (depth > model.nodes.size())
        return dm_fail(err, DM_ERR_FORMAT, "%s: nodes[%d] is its own ancestor (a cycle), expected a tree", path, node);
    const tinygltf::Node &n = model.nodes[(size_t)node];
    double local[16], world[16];
    dm_result r = local_matrix(path, n, node, local, err);
    if (r != DM_OK) return r;
    mat_mul(parent, local, world);
    if (n.mesh >= 0) {
        if ((size_t)n.mesh >= model.meshes.size())
            return dm_fail(err, DM_ERR_FORMAT, "%s: nodes[%d].mesh = %d, expected < %zu", path, node, n.mesh,
                           model.meshes.size());
        dm_gltf::instance in;
        in.mesh = n.mesh;
        std::memcpy(in.m, world, sizeof world);
        out->push_back(in);
    }
    for (int child : n.children)
        if ((r = visit(path, model, child, world, depth + 1, out, err)) != DM_OK) return r;
    return DM_OK;
}

// ---- accessors ----------------------------------------------------------------------

struct view {
    const unsigned char *data;
    size_t stride, count;
    int type, components; // TINYGLTF_COMPONENT_TYPE_*, 1..16
    bool normalized;
};

// Validates accessor `index` against its buffer view and buffer; `what` names it.
dm_result accessor_view(const char *path, const tinygltf::Model &model, int index, const std::string &what, view *v,
                        dm_error *err)
{
    const char *w = what.c_str();
    if (index < 0 || (size_t)index >= model.accessors.size())
        return dm_fail(err, DM_ERR_FORMAT, "%s: %s: accessor %d, expected < %zu", path, w, index, model.accessors.size());
    const tinygltf::Accessor &a = model.accessors[(size_t)index];
    if (a.sparse.isSparse)
        return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: %s: accessor %d is sparse, which dermis does not read", path, w,
                       index);
    if (a.bufferView < 0 || (size_t)a.bufferView >= model.bufferViews.size())
        return dm_fail(err, DM_ERR_FORMAT, "%s: %s: accessor %d has buffer view %d, expected one in [0, %zu)", path, w,
                       index, a.bufferView, model.bufferViews.size());
    const tinygltf::BufferView &bv = model.bufferViews[(size_t)a.bufferView];
    if (bv.buffer < 0 || (size_t)bv.buffer >= model.buffers.size())
        return dm_fail(err, DM_ERR_FORMAT, "%s: %s: buffer view %d has buffer %d, expected < %zu", path, w,
                       a.bufferView, bv.buffer, model.buffers.size());
    const size_t buffer_size = model.buffers[(size_t)bv.buffer].data.size();
    if (bv.byteOffset > buffer_size || bv.byteLength > buffer_size - bv.byteOffset)
        return dm_fail(err, DM_ERR_FORMAT, "%s: %s: buffer view %d spans bytes [%zu, %zu + %zu), buffer %d has %zu",
                       path, w, a.bufferView, bv.byteOffset, bv.byteOffset, bv.byteLength, bv.buffer, buffer_size);
    const int csize = tinygltf::GetComponentSizeInBytes((uint32_t)a.componentType);
    const int ncomp = tinygltf::GetNumComponentsInType((uint32_t)a.type);
    const int stride = a.ByteStride(bv);
    if (csize <= 0 || ncomp <= 0 || stride <= 0)
        return dm_fail(err, DM_ERR_FORMAT, "%s: %s: accessor %d: component type %d, type %d, stride %zu not valid", path,
                       w, index, a.componentType, a.type, bv.byteStride);
    const size_t elem = (size_t)csize * (size_t)ncomp;
    if (a.count == 0) return dm_fail(err, DM_ERR_EMPTY, "%s: %s: accessor %d has no elements", path, w, index);
    // Last element's end, in 128-bit-safe steps: count ≤ byteLength bounds the product.
    if (a.count > bv.byteLength || a.byteOffset > bv.byteLength ||
        (a.count - 1) * (size_t)stride > bv.byteLength - a.byteOffset ||
        elem > bv.byteLength - a.byteOffset - (a.count - 1) * (size_t)stride)
        return dm_fail(err, DM_ERR_FORMAT,
                       "%s: %s: accessor %d (%zu elements of %zu bytes, stride %d, offset %zu) runs past its buffer "
                       "view %d of %zu bytes",
                       path, w, index, a.count, elem, stride, a.byteOffset, a.bufferView, bv.byteLength);
    v->data = model.buffers[(size_t)bv.buffer].data.data() + bv.byteOffset + a.byteOffset;
    v->stride = (size_t)stride;
    v->count = a.count;
    v->type = a.componentType;
    v->components = ncomp;
    v->normalized = a.normalized;
    return DM_OK;
}

// Element i, component c as a double (floats, normalized or plain integers).
double get(const view &v, size_t i, int c)
{
    const unsigned char *p = v.data + i * v.stride;
    switch (v.type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p + 4 * c, 4); return f; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return v.normalized ? p[c] / 255.0 : p[c];
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t u; std::memcpy(&u, p + 2 * c, 2); return v.normalized ? u / 65535.0 : u; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t u; std::memcpy(&u, p + 4 * c, 4); return u; }
    default: return 0.0; // refused by the callers' type checks
    }
}

dm_result want_float(const char *path, const std::string &what, const view &v, int components, bool or_unorm,
                     dm_error *err)
{
    bool ok_type = v.type == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                   (or_unorm && v.normalized &&
                    (v.type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || v.type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
    if (!ok_type || v.components != components)
        return dm_fail(err, DM_ERR_FORMAT, "%s: %s: component type %d with %d components, expected %s VEC%d", path,
                       what.c_str(), v.type, v.components, or_unorm ? "float or normalized u8/u16" : "float",
                       components);
    return DM_OK;
}

// The merged mesh before welding: per vertex positions/normals/tangents, per corner UVs.
struct soup {
    std::vector<double> pos, nrm, tan; // 3, 3, 4 per vertex
    std::vector<uint32_t> idx;         // 3 per triangle
    std::vector<float> uv;             // 2 per corner
    bool normals = true, tangents = true;
};

dm_result read_primitive(const char *path, const tinygltf::Model &model, const dm_gltf::instance &in, size_t pi,
                         const dm_mesh_load_options &o, soup *s, dm_error *err)
{
    const tinygltf::Mesh &mesh = model.meshes[(size_t)in.mesh];
    const tinygltf::Primitive &p = mesh.primitives[pi];
    char where[256];
    std::snprintf(where, sizeof where, "meshes[%d] (\"%.60s\") primitive %zu", in.mesh, mesh.name.c_str(), pi);
    const std::string at(where);
    if (p.extensions.count("KHR_draco_mesh_compression"))
        return dm_fail(err, DM_ERR_UNSUPPORTED,
                       "%s: %s is Draco-compressed (KHR_draco_mesh_compression), which dermis does not read; "
                       "expected plain accessors (decompress it first, e.g. gltf-transform copy)",
                       path, where);
    if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP || p.mode == TINYGLTF_MODE_TRIANGLE_FAN)
        return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: %s: mode %d (triangle strip/fan), expected triangles (4)", path,
                       where, p.mode);
    if (p.mode != -1 && p.mode != TINYGLTF_MODE_TRIANGLES) return DM_OK; // points and lines: nothing to bake
    auto attr = [&](const char *name) {
        auto it = p.attributes.find(name);
        return it == p.attributes.end() ? -1 : it->second;
    };
    const int ipos = attr("POSITION"), inrm = attr("NORMAL"), itan = attr("TANGENT"), iuv = attr("TEXCOORD_0");
    if (ipos < 0) return dm_fail(err, DM_ERR_FORMAT, "%s: %s has no POSITION, expected one", path, where);
    if (iuv < 0 && !o.uvs_optional)
        return dm_fail(err, DM_ERR_FORMAT, "%s: %s has no TEXCOORD_0, expected a UV layout", path, where);
    view vp, vn = {}, vt = {}, vu = {}, vi = {};
    dm_result r = accessor_view(path, model, ipos, at + " POSITION", &vp, err);
    if (r == DM_OK) r = want_float(path, at + " POSITION", vp, 3, false, err);
    if (r == DM_OK && inrm >= 0 && (r = accessor_view(path, model, inrm, at + " NORMAL", &vn, err)) == DM_OK)
        r = want_float(path, at + " NORMAL", vn, 3, false, err);
    if (r == DM_OK && itan >= 0 && (r = accessor_view(path, model, itan, at + " TANGENT", &vt, err)) == DM_OK)
        r = want_float(path, at + " TANGENT", vt, 4, false, err);
    if (r == DM_OK && iuv >= 0 && (r = accessor_view(path, model, iuv, at + " TEXCOORD_0", &vu, err)) == DM_OK)
        r = want_float(path, at + " TEXCOORD_0", vu, 2, true, err);
    if (r != DM_OK) return r;
    const size_t n = vp.count;
    for (const view *v : {&vn, &vt, &vu})
        if (v->data && v->count != n)
            return dm_fail(err, DM_ERR_FORMAT, "%s: %s: an attribute has %zu elements, POSITION has %zu, expected equal",
                           path, where, v->count, n);
    size_t corners = n;
    if (p.indices >= 0) {
        if ((r = accessor_view(path, model, p.indices, at + " indices", &vi, err)) != DM_OK) return r;
        if (vi.components != 1 || (vi.type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                   vi.type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                   vi.type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
            return dm_fail(err, DM_ERR_FORMAT, "%s: %s: indices of component type %d, expected scalar u8, u16 or u32",
                           path, where, vi.type);
        vi.normalized = false;
        corners = vi.count;
    }
    if (corners % 3 != 0)
        return dm_fail(err, DM_ERR_FORMAT, "%s: %s: %zu corners, expected a multiple of 3", path, where, corners);
    const size_t base = s->pos.size() / 3;
    if (base + n > (size_t)INT32_MAX || s->idx.size() / 3 + corners / 3 > (size_t)DM_MESH_TRIANGLES_MAX)
        return dm_fail(err, DM_ERR_RANGE, "%s: more than %d triangles or %d vertices, too many", path,
                       (int)DM_MESH_TRIANGLES_MAX, (int)INT32_MAX);
    // Positions by the world matrix; normals by its inverse transpose (columns c[0..2],
    // c[3..5], c[6..8]: the cross products of the matrix's columns = det · M^-T),
    // tangents by its linear part; a mirroring matrix flips the winding and w.
    const double *m = in.m;
    const double c[9] = {m[5] * m[10] - m[6] * m[9], m[6] * m[8] - m[4] * m[10], m[4] * m[9] - m[5] * m[8],
                         m[9] * m[2] - m[10] * m[1], m[10] * m[0] - m[8] * m[2], m[8] * m[1] - m[9] * m[0],
                         m[1] * m[6] - m[2] * m[5], m[2] * m[4] - m[0] * m[6], m[0] * m[5] - m[1] * m[4]};
    const double det = m[0] * c[0] + m[1] * c[1] + m[2] * c[2];
    const bool is_identity = std::memcmp(m, identity, sizeof identity) == 0;
    for (size_t i = 0; i < n; ++i) {
        double x = get(vp, i, 0), y = get(vp, i, 1), z = get(vp, i, 2);
        if (is_identity) {
            s->pos.insert(s->pos.end(), {x, y, z});
        } else {
            for (int d = 0; d < 3; ++d) s->pos.push_back(m[d] * x + m[4 + d] * y + m[8 + d] * z + m[12 + d]);
        }
        if (vn.data) {
            double a = get(vn, i, 0), b = get(vn, i, 1), e = get(vn, i, 2);
            if (is_identity)
                s->nrm.insert(s->nrm.end(), {a, b, e});
            else
                for (int d = 0; d < 3; ++d) // cofactors = det · inverse transpose: keep the sign right
                    s->nrm.push_back((det < 0 ? -1.0 : 1.0) * (c[d] * a + c[3 + d] * b + c[6 + d] * e));
        }
        if (vt.data) {
            double a = get(vt, i, 0), b = get(vt, i, 1), e = get(vt, i, 2), w = get(vt, i, 3);
            for (int d = 0; d < 3; ++d) s->tan.push_back(is_identity ? get(vt, i, d) : m[d] * a + m[4 + d] * b + m[8 + d] * e);
            s->tan.push_back(det < 0 ? -w : w);
        }
    }
    s->normals = s->normals && vn.data;
    s->tangents = s->tangents && vt.data && vn.data;
    for (size_t t = 0; t < corners; t += 3) {
        size_t k[3];
        for (int q = 0; q < 3; ++q) {
            k[q] = vi.data ? (size_t)get(vi, t + (size_t)q, 0) : t + (size_t)q;
            if (k[q] >= n)
                return dm_fail(err, DM_ERR_RANGE, "%s: %s: index %zu at position %zu, expected < %zu (POSITION count)",
                               path, where, k[q], t + (size_t)q, n);
        }
        if (det < 0) std::swap(k[1], k[2]);
        for (int q = 0; q < 3; ++q) {
            s->idx.push_back((uint32_t)(base + k[q]));
            float u = vu.data ? (float)get(vu, k[q], 0) : 0.0f, v = vu.data ? (float)get(vu, k[q], 1) : 1.0f;
            s->uv.push_back(u);
            s->uv.push_back(1.0f - v); // glTF's v points down
        }
    }
    return DM_OK;
}

} // namespace

extern "C" int dm_mesh_is_gltf(const char *path)
{
    return ends_with_ci(path, ".gltf") || ends_with_ci(path, ".glb");
}

namespace dm_gltf {

dm_result load(const char *path, bool keep_images, tinygltf::Model *model, dm_error *err)
{
    const bool glb = ends_with_ci(path, ".glb");
    if (glb) {
        dm_result r = check_glb_header(path, err);
        if (r != DM_OK) return r;
    }
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(keep_image, keep_images ? model : nullptr);
    // A name without a folder gets "./", so that tinygltf's base folder is never empty.
    const std::string name = std::strchr(path, '/') ? std::string(path) : "./" + std::string(path);
    fs_guard guard;
    guard.gltf = path;
    const std::string base = name.substr(0, name.find_last_of("/\\")); // tinygltf's GetBaseDir
    guard.prefix = base.empty() || base.back() == '/' ? base : base + "/";
    loader.SetFsCallbacks(tinygltf::FsCallbacks{fs_exists, fs_expand, fs_read, fs_write, &guard});
    std::string e, w;
    bool ok = false;
    try {
        ok = glb ? loader.LoadBinaryFromFile(model, &e, &w, name) : loader.LoadASCIIFromFile(model, &e, &w, name);
    } catch (const std::bad_alloc &) {
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory while reading", path);
    } catch (const std::exception &x) {
        e = x.what();
    }
    if (!guard.refusal.empty()) return dm_fail(err, DM_ERR_FILE_OPEN, "%s", guard.refusal.c_str());
    if (!ok) return dm_fail(err, DM_ERR_FORMAT, "%s: not a valid glTF 2.0 file: %s", path, one_line(e).c_str());
    for (const std::string &x : model->extensionsRequired)
        if (x == "KHR_draco_mesh_compression" || x == "EXT_meshopt_compression" || x == "KHR_mesh_quantization")
            return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: requires %s, which dermis does not read%s", path, x.c_str(),
                           x == "KHR_draco_mesh_compression" ? " (Draco-compressed meshes)" : "");
    return DM_OK;
}

dm_result instances(const char *path, const tinygltf::Model &model, const char *mesh_name, std::vector<instance> *out,
                    dm_error *err)
{
    std::vector<instance> all;
    if (model.scenes.empty()) {
        for (size_t k = 0; k < model.meshes.size(); ++k) {
            instance in;
            in.mesh = (int)k;
            std::memcpy(in.m, identity, sizeof identity);
            all.push_back(in);
        }
    } else {
        int sc = model.defaultScene;
        if (sc < 0) sc = 0;
        if ((size_t)sc >= model.scenes.size())
            return dm_fail(err, DM_ERR_FORMAT, "%s: scene %d, expected < %zu", path, sc, model.scenes.size());
        for (int node : model.scenes[(size_t)sc].nodes) {
            dm_result r = visit(path, model, node, identity, 0, &all, err);
            if (r != DM_OK) return r;
        }
    }
    out->clear();
    for (const instance &in : all)
        if (!mesh_name || !*mesh_name || model.meshes[(size_t)in.mesh].name == mesh_name) out->push_back(in);
    if (out->empty() && mesh_name && *mesh_name) {
        std::string names;
        for (const tinygltf::Mesh &m : model.meshes) names += (names.empty() ? "\"" : ", \"") + m.name + "\"";
        return dm_fail(err, DM_ERR_MISMATCH, "%s: no mesh named \"%s\" in the scene, the file has %s", path, mesh_name,
                       names.empty() ? "none" : one_line(names).c_str());
    }
    if (out->empty()) return dm_fail(err, DM_ERR_EMPTY, "%s: the scene places no mesh, expected one", path);
    return DM_OK;
}

} // namespace dm_gltf

extern "C" dm_result dm_mesh_read_gltf(const char *path, const dm_mesh_load_options *opt, dm_mesh *out, dm_error *err)
{
    std::memset(out, 0, sizeof *out);
    dm_mesh_load_options o = {};
    if (opt) o = *opt;
    try {
        tinygltf::Model model;
        dm_result r = dm_gltf::load(path, false, &model, err);
        std::vector<dm_gltf::instance> inst;
        if (r == DM_OK) r = dm_gltf::instances(path, model, o.mesh_name, &inst, err);
        soup s;
        for (const dm_gltf::instance &in : inst)
            for (size_t pi = 0; r == DM_OK && pi < model.meshes[(size_t)in.mesh].primitives.size(); ++pi)
                r = read_primitive(path, model, in, pi, o, &s, err);
        if (r != DM_OK) return r;
        if (s.idx.empty()) return dm_fail(err, DM_ERR_EMPTY, "%s: no triangles (points or lines only), expected a mesh", path);
        for (double t : s.tan)
            if (!std::isfinite(t))
                return dm_fail(err, DM_ERR_NON_FINITE, "%s: a TANGENT is not finite (%g), expected finite numbers", path, t);
        // Weld: vertices glTF split at UV seams share one position index again (first
        // occurrence order, bit-identical float position, −0 = +0).
        const size_t nv = s.pos.size() / 3;
        std::vector<uint32_t> remap(nv);
        std::vector<float> welded;
        struct key_hash {
            size_t operator()(const std::array<uint32_t, 3> &k) const
            {
                return (size_t)k[0] * 0x9E3779B97F4A7C15ull ^ (size_t)k[1] * 0xC2B2AE3D27D4EB4Full ^ k[2];
            }
        };
        std::unordered_map<std::array<uint32_t, 3>, uint32_t, key_hash> seen;
        seen.reserve(nv);
        for (size_t i = 0; i < nv; ++i) {
            float f[3];
            std::array<uint32_t, 3> k;
            for (int d = 0; d < 3; ++d) {
                f[d] = (float)s.pos[i * 3 + (size_t)d] + 0.0f;
                std::memcpy(&k[(size_t)d], &f[d], 4);
            }
            auto ins = seen.emplace(k, (uint32_t)(welded.size() / 3));
            if (ins.second) welded.insert(welded.end(), f, f + 3);
            remap[i] = ins.first->second;
        }
        const size_t tris = s.idx.size() / 3;
        if ((r = dm_mesh_alloc((int32_t)(welded.size() / 3), (int32_t)tris, out, err)) != DM_OK) return r;
        out->polygon_count = (int64_t)tris;
        out->normals_from_file = s.normals ? 1 : 0;
        std::memcpy(out->positions, welded.data(), welded.size() * sizeof(float));
        std::memcpy(out->uvs, s.uv.data(), s.uv.size() * sizeof(float));
        if (s.tangents && !(out->tangents = static_cast<float *>(std::malloc(tris * 12 * sizeof(float))))) {
            dm_mesh_free(out);
            return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
        }
        for (size_t k = 0; k < tris * 3; ++k) {
            const size_t v = s.idx[k];
            out->indices[k] = remap[v];
            if (s.normals)
                for (int d = 0; d < 3; ++d) out->normals[k * 3 + (size_t)d] = (float)s.nrm[v * 3 + (size_t)d];
            if (s.tangents)
                for (int d = 0; d < 4; ++d) out->tangents[k * 4 + (size_t)d] = (float)s.tan[v * 4 + (size_t)d];
        }
        return DM_OK;
    } catch (const std::bad_alloc &) {
        dm_mesh_free(out);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory while reading", path);
    }
}
