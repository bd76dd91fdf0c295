/* dm_reference_memory.c — what a dermis-reference run holds at its peak (its formula:
 * reference/dm_reference.h, "memory"), and the refusal of a run that would not fit. */
#include <stdio.h>

#include "reference/dm_reference.h"
#include "reference/dm_ref_frame.h"
#include "core/dm_memory.h"
#include "pack/dm_pack.h"
#include "core/dm_scene.h"

static uint64_t sq(int n)
{
    return (uint64_t)(n > 0 ? n : 0) * (uint64_t)(n > 0 ? n : 0);
}

static uint64_t max_u64(uint64_t a, uint64_t b)
{
    return a > b ? a : b;
}

void dm_reference_memory_estimate(const dm_pack *pack, const dm_reference_memory_options *o, dm_reference_memory *m)
{
    *m = (dm_reference_memory){.base_size = DM_REFERENCE_MEMORY_BASE_SIZE + (uint64_t)pack->size};
    if (o->texture_space > 0) {
        /* the irradiance pass: the renderer (its driver and the pack's textures counted there) and the atlas */
        uint64_t n2 = sq(o->texture_space);
        /* the pack stays open beside the renderer: its entries are read from it */
        m->irradiance_size = o->irradiance_render_size + n2 * 16 + (uint64_t)pack->size;
        m->convolution_size = n2 * (16 + 16 + 20 + 4 + 48 + 12 + 16 + 24 * (uint64_t)(o->level_count > 0 ? o->level_count : 0));
        m->total_size = max_u64(m->irradiance_size, m->base_size + m->convolution_size);
        return;
    }
    dm_scene scene;
    int w = o->width, h = o->height;
    if ((!w || !h) && dm_pack_scene(pack, &scene, NULL) == DM_OK) w = scene.width, h = scene.height;
    int a = o->atlas_size > 0 ? o->atlas_size : DM_REF_FRAME_ATLAS_DEFAULT;
    int k = dm_ref_frame_atlas_samples(a, o->atlas_samples > 0 ? o->atlas_samples : 0);
    m->irradiance_size = sq(a) * 16 + sq(a * k) * 20;
    m->convolution_size = sq(a) * (16 + 16 + 48);
    /* per pixel 80 bytes; per skin pixel (every pixel, at most) and sub-pixel ray its hit,
     * index, convolution target and result: 44 bytes */
    uint64_t ps = (uint64_t)(o->pixel_samples > 0 ? o->pixel_samples : 3);
    uint64_t rs = (uint64_t)(o->refine_samples > 0 ? o->refine_samples : 0);
    m->pixels_size = (uint64_t)(w > 0 ? w : 0) * (uint64_t)(h > 0 ? h : 0) * (80 + 44 * ps * ps + (rs ? 12 + 44 * rs * rs : 0));
    m->total_size = m->base_size + max_u64(m->irradiance_size, m->convolution_size) + m->pixels_size;
}

dm_result dm_reference_memory_check(const dm_pack *pack, const dm_reference_memory_options *o, dm_error *err)
{
    dm_reference_memory m;
    dm_reference_memory_estimate(pack, o, &m);
    char what[96], detail[256], irr[32], conv[32], px[32], base[32];
    dm_memory_size_text(m.irradiance_size, irr, sizeof irr);
    dm_memory_size_text(m.convolution_size, conv, sizeof conv);
    dm_memory_size_text(m.pixels_size, px, sizeof px);
    dm_memory_size_text(m.base_size, base, sizeof base);
    if (o->texture_space > 0) {
        snprintf(what, sizeof what, "--texture-space %d", o->texture_space);
        snprintf(detail, sizeof detail, "the irradiance pass %s with the renderer; the convolution %s, and %s for the pack and libraries",
                 irr, conv, base);
    } else {
        snprintf(what, sizeof what, "the frame (atlas %d)", o->atlas_size > 0 ? o->atlas_size : DM_REF_FRAME_ATLAS_DEFAULT);
        snprintf(detail, sizeof detail, "irradiance atlas %s, convolution %s, pixels %s, pack and libraries %s", irr,
                 conv, px, base);
    }
    return dm_memory_check(m.total_size, what, detail,
                           o->texture_space > 0 ? "lower --texture-space"
                                                : "lower --atlas, --atlas-samples or --size",
                           err);
}
