// dm_image_oiio.cpp — the OpenImageIO adapter behind dm_image.h. C++ stays in here.
#include "bake/dm_image.h"

#include <cassert>
#include <cstdlib>
#include <cstring>
#include <string>

#include <OpenImageIO/imageio.h>

#include "core/dm_file.h"

using namespace OIIO;

static TypeDesc to_oiio(dm_pixel_type t)
{
    switch (t) {
    case DM_PIXEL_U8: return TypeDesc::UINT8;
    case DM_PIXEL_U16: return TypeDesc::UINT16;
    default: return TypeDesc::FLOAT;
    }
}

extern "C" size_t dm_image_size(const dm_image *img)
{
    return (size_t)img->width * (size_t)img->height * (size_t)img->channels * (size_t)img->type;
}

extern "C" dm_result dm_png_write(const char *path, const dm_image *img, const dm_provenance *prov, dm_error *err)
{
    assert(path && img && prov);
    if (img->type != DM_PIXEL_U8 && img->type != DM_PIXEL_U16)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: PNG holds 8 or 16 bits per channel only", path);
    if (img->width <= 0 || img->height <= 0 || img->channels < 1 || img->channels > 4 || !img->pixels)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: image %dx%dx%d is empty or has no pixels", path,
                       img->width, img->height, img->channels);
    char json[16384];
    dm_result r = dm_prov_to_json(prov, json, sizeof json, err);
    if (r != DM_OK) return r;
    dm_atomic_file af;
    if ((r = dm_atomic_begin(&af, path, err)) != DM_OK) return r;

    auto out = ImageOutput::create("png"); // by format name: the temporary name has no .png
    if (!out) {
        dm_atomic_abort(&af);
        return dm_fail(err, DM_ERR_UNSUPPORTED, "%s: OpenImageIO has no PNG writer (%s)", path,
                       OIIO::geterror().c_str());
    }
    ImageSpec spec(img->width, img->height, img->channels, to_oiio(img->type));
    spec.attribute("Software", std::string(prov->tool) + " " + prov->version);
    spec.attribute("dermis:provenance", json);
    spec.attribute("png:compressionLevel", 6);
    if (img->channels == 4) spec.attribute("oiio:UnassociatedAlpha", 1);
    const size_t row_bytes = (size_t)img->width * img->channels * img->type;
    const unsigned char *last_row = (const unsigned char *)img->pixels + row_bytes * (img->height - 1);
    bool ok = out->open(af.tmp_path, spec) &&
              out->write_image(to_oiio(img->type), last_row, AutoStride, -(stride_t)row_bytes, AutoStride);
    std::string msg = ok ? std::string() : out->geterror();
    ok = out->close() && ok;
    if (!ok) {
        if (msg.empty()) msg = out->geterror();
        dm_atomic_abort(&af);
        return dm_fail(err, DM_ERR_FILE_WRITE, "%s: %s", path, msg.c_str());
    }
    return dm_atomic_commit(&af, err);
}

extern "C" void dm_image_free(dm_image *img)
{
    if (!img) return;
    std::free(img->pixels);
    std::memset(img, 0, sizeof *img);
}

extern "C" dm_result dm_image_read(const char *path, dm_pixel_type type, dm_image *out, dm_error *err)
{
    assert(path && out);
    std::memset(out, 0, sizeof *out);
    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = ImageInput::open(path, &config);
    if (!in) {
        std::string e = OIIO::geterror();
        FILE *probe = std::fopen(path, "rb");
        if (!probe) return dm_fail(err, DM_ERR_FILE_OPEN, "%s: cannot open (%s)", path, e.c_str());
        std::fclose(probe);
        return dm_fail(err, DM_ERR_FORMAT, "%s: not a readable image (%s)", path, e.c_str());
    }
    const ImageSpec &spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels < 1 || spec.depth != 1 ||
        (int64_t)spec.width * spec.height > ((int64_t)1 << 28)) {
        in->close();
        return dm_fail(err, DM_ERR_FORMAT, "%s: image %dx%dx%d (depth %d) is out of range", path, spec.width,
                       spec.height, spec.nchannels, spec.depth);
    }
    out->width = spec.width;
    out->height = spec.height;
    out->channels = spec.nchannels > 4 ? 4 : spec.nchannels;
    out->type = type;
    out->pixels = std::malloc(dm_image_size(out));
    if (!out->pixels) {
        in->close();
        dm_image_free(out);
        return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory for %dx%d", path, spec.width, spec.height);
    }
    const size_t row_bytes = (size_t)out->width * out->channels * out->type;
    unsigned char *last_row = (unsigned char *)out->pixels + row_bytes * (out->height - 1);
    bool ok = in->read_image(0, 0, 0, out->channels, to_oiio(type), last_row, AutoStride, -(stride_t)row_bytes);
    std::string prov = spec.get_string_attribute("dermis:provenance");
    std::string msg = ok ? std::string() : in->geterror();
    in->close();
    if (!ok) {
        dm_image_free(out);
        return dm_fail(err, DM_ERR_FORMAT, "%s: cannot decode pixels (%s)", path, msg.c_str());
    }
    if (!prov.empty()) out->has_provenance = dm_prov_from_json(&out->prov, prov.c_str(), path, nullptr) == DM_OK;
    return DM_OK;
}
