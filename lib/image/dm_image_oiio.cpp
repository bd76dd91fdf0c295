// dm_image_oiio.cpp — the OpenImageIO adapter behind dm_image.h. C++ stays in here.
#include "image/dm_image.h"
#include "core/dm_input.h"

#include <cassert>
#include <cstdlib>
#include <cstring>
#include <string>

#include <OpenImageIO/imageio.h>


using namespace OIIO;

static TypeDesc to_oiio(dm_pixel_type t)
{
    switch (t) {
    case DM_PIXEL_U8: return TypeDesc::UINT8;
    case DM_PIXEL_U16: return TypeDesc::UINT16;
    default: return TypeDesc::FLOAT;
    }
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
    dm_result r = dm_input_check(path, DM_INPUT_IMAGE, nullptr, err); // OpenImageIO opens it by name
    if (r != DM_OK) return r;
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
