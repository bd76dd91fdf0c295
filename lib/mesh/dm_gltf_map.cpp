// dm_gltf_map.cpp — a glTF material's baseColor and normal textures (dm_gltf_map.h).
// tinygltf parses in a child (dm_isolate.h), which sends back the image's URI and bytes.
#include "mesh/dm_gltf_map.h"

#include "mesh/dm_isolate.h"
#include "mesh/dm_mesh_gltf.h"
#include "core/dm_input.h"
#include "core/dm_uri.h"

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <unistd.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <tiny_gltf.h>
#pragma GCC diagnostic pop

namespace {

struct map_query {
    const char *path, *mesh_name;
    dm_gltf_map which;
    bool want_bytes;
    // filled in the parent
    int found = 0, image = -1;
    std::string uri, mime;
    std::vector<unsigned char> bytes;
};

// In the child: finds the image; returns the result, fills q.
dm_result find_image(map_query &q, dm_error *err)
{
    tinygltf::Model model;
    dm_result r = dm_gltf::load(q.path, q.want_bytes, &model, err);
    std::vector<dm_gltf::instance> inst;
    if (r == DM_OK) r = dm_gltf::instances(q.path, model, q.mesh_name, &inst, err);
    if (r != DM_OK) return r;
    int material = -1;
    for (const dm_gltf::instance &in : inst) {
        for (const tinygltf::Primitive &p : model.meshes[(size_t)in.mesh].primitives)
            if (p.mode == -1 || p.mode == TINYGLTF_MODE_TRIANGLES) {
                material = p.material;
                break;
            }
        if (material != -1) break;
    }
    if (material < 0) return DM_OK;
    if ((size_t)material >= model.materials.size())
        return dm_fail(err, DM_ERR_FORMAT, "%s: material %d, expected < %zu", q.path, material, model.materials.size());
    const tinygltf::Material &m = model.materials[(size_t)material];
    const int texture = q.which == DM_GLTF_MAP_BASE_COLOR ? m.pbrMetallicRoughness.baseColorTexture.index
                                                          : m.normalTexture.index;
    if (texture < 0) return DM_OK;
    if ((size_t)texture >= model.textures.size())
        return dm_fail(err, DM_ERR_FORMAT, "%s: materials[%d]: texture %d, expected < %zu", q.path, material, texture,
                       model.textures.size());
    const int image = model.textures[(size_t)texture].source;
    if (image < 0) return DM_OK; // an extension's image source only (e.g. KHR_texture_basisu)
    if ((size_t)image >= model.images.size())
        return dm_fail(err, DM_ERR_FORMAT, "%s: textures[%d]: image %d, expected < %zu", q.path, texture, image,
                       model.images.size());
    const tinygltf::Image &img = model.images[(size_t)image];
    q.found = 1;
    q.image = image;
    if (!img.uri.empty() && img.uri.compare(0, 5, "data:") != 0) q.uri = img.uri;
    q.mime = img.mimeType;
    if (q.want_bytes) {
        if (q.uri.empty() && img.image.empty())
            return dm_fail(err, DM_ERR_FORMAT, "%s: images[%d] has no data, expected an embedded PNG or JPEG", q.path,
                           image);
        q.bytes = img.image;
    }
    return DM_OK;
}

bool send_string(int fd, const std::string &s)
{
    uint64_t n = s.size();
    return dm_isolate_write(fd, &n, sizeof n) && dm_isolate_write(fd, s.data(), s.size());
}

bool recv_bytes(dm_isolate_pipe *pp, std::vector<unsigned char> *out)
{
    uint64_t n = 0;
    if (!dm_isolate_read(pp, &n, sizeof n)) return false;
    if (n > ((uint64_t)1 << 32)) return pp->lost = 1, false; // a GLB cannot hold more
    out->resize((size_t)n);
    return n == 0 || dm_isolate_read(pp, out->data(), (size_t)n);
}

void map_in_child(void *ctx, int fd)
{
    map_query &q = *static_cast<map_query *>(ctx);
    dm_error e = {};
    dm_result r;
    try {
        r = find_image(q, &e);
    } catch (const std::bad_alloc &) {
        r = dm_fail(&e, DM_ERR_OUT_OF_MEMORY, "%s: out of memory while reading", q.path);
    }
    if (!dm_isolate_write_result(fd, r, &e) || r != DM_OK) return;
    int32_t head[2] = {q.found, q.image};
    std::string bytes(q.bytes.begin(), q.bytes.end());
    dm_isolate_write(fd, head, sizeof head) && send_string(fd, q.uri) && send_string(fd, q.mime) &&
        send_string(fd, bytes);
}

dm_result map_in_parent(void *ctx, dm_isolate_pipe *pp, dm_error *err)
{
    map_query &q = *static_cast<map_query *>(ctx);
    dm_result r = DM_OK;
    if (!dm_isolate_read_result(pp, &r, err) || r != DM_OK) return r;
    int32_t head[2];
    std::vector<unsigned char> uri, mime;
    if (!dm_isolate_read(pp, head, sizeof head) || !recv_bytes(pp, &uri) || !recv_bytes(pp, &mime) ||
        !recv_bytes(pp, &q.bytes))
        return DM_ERR_FORMAT;
    q.found = head[0], q.image = head[1];
    q.uri.assign(uri.begin(), uri.end());
    q.mime.assign(mime.begin(), mime.end());
    return DM_OK;
}

dm_result query(map_query &q, dm_error *err)
{
    dm_result r = dm_input_check(q.path, DM_INPUT_MESH, nullptr, err); // here: a FIFO must not reach the child
    if (r != DM_OK) return r;
    return dm_isolate_run(q.path, dm_isolate_limit_ms(q.path), map_in_child, map_in_parent, &q, err);
}

void describe(const map_query &q, char *source, size_t size)
{
    if (!source || !size) return;
    if (!q.found)
        std::snprintf(source, size, "none");
    else if (!q.uri.empty())
        std::snprintf(source, size, "images[%d] \"%.200s\"", q.image, q.uri.c_str());
    else
        std::snprintf(source, size, "images[%d] (%.40s, embedded)", q.image, q.mime.empty() ? "?" : q.mime.c_str());
}

} // namespace

extern "C" int dm_gltf_is_file(const char *path)
{
    return dm_mesh_is_gltf(path);
}

extern "C" dm_result dm_gltf_map_find(const char *path, const char *mesh_name, dm_gltf_map which, int *found,
                                      char *source, size_t source_size, dm_error *err)
{
    map_query q;
    q.path = path, q.mesh_name = mesh_name, q.which = which, q.want_bytes = false;
    dm_result r = query(q, err);
    *found = r == DM_OK ? q.found : 0;
    describe(q, source, source_size);
    return r;
}

extern "C" dm_result dm_gltf_map_read(const char *path, const char *mesh_name, dm_gltf_map which, dm_pixel_type type,
                                      dm_image *out, char *source, size_t source_size, dm_error *err)
{
    std::memset(out, 0, sizeof *out);
    map_query q;
    q.path = path, q.mesh_name = mesh_name, q.which = which, q.want_bytes = true;
    dm_result r = query(q, err);
    describe(q, source, source_size);
    if (r != DM_OK) return r;
    const char *what = which == DM_GLTF_MAP_BASE_COLOR ? "baseColorTexture" : "normalTexture";
    if (!q.found) return dm_fail(err, DM_ERR_EMPTY, "%s: the material has no %s, expected one", path, what);
    if (!q.uri.empty()) { // an external file, inside the glTF's folder (core/dm_uri.h)
        std::vector<char> file(8192);
        r = dm_uri_resolve(path, q.uri.c_str(), true, file.data(), file.size(), nullptr, err);
        return r != DM_OK ? r : dm_image_read(file.data(), type, out, err);
    }
    // Embedded: through a temporary file named by the image's type (OpenImageIO picks
    // its reader by extension first).
    const char *ext = q.mime == "image/jpeg" ? ".jpg" : q.mime == "image/png" ? ".png" : ".img";
    const char *tmp = std::getenv("TMPDIR");
    std::string name = std::string(tmp && *tmp ? tmp : "/tmp") + "/dermis-gltf-image-XXXXXX" + ext;
    std::vector<char> buf(name.begin(), name.end());
    buf.push_back('\0');
    int fd = ::mkstemps(buf.data(), (int)std::strlen(ext));
    if (fd < 0) return dm_fail(err, DM_ERR_FILE_WRITE, "%s: cannot make a temporary file (%s)", buf.data(), std::strerror(errno));
    bool ok = dm_isolate_write(fd, q.bytes.data(), q.bytes.size());
    ::close(fd);
    if (!ok) {
        ::unlink(buf.data());
        return dm_fail(err, DM_ERR_FILE_WRITE, "%s: cannot write the embedded image", buf.data());
    }
    r = dm_image_read(buf.data(), type, out, err);
    ::unlink(buf.data());
    if (r != DM_OK) {
        // name the glTF file and the image, not the temporary file
        std::string detail = err ? err->detail : "";
        dm_fail(err, r, "%s: %s images[%d] (%s, embedded): cannot be read as an image (%.300s)", path, what, q.image,
                q.mime.c_str(), detail.c_str());
    }
    return r;
}
