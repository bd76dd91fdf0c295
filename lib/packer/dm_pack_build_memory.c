/* dm_pack_build_memory.c — what a pack build holds at its peak, by the scene's sizes (the
 * formula: packer/dm_pack_build.h), and the refusal of a build that would not fit. */
#include <stdio.h>

#include "bake/dm_thin_gather.h"
#include "packer/dm_pack_build.h"
#include "core/dm_memory.h"

void dm_pack_build_memory_estimate(const dm_pack_build *b, dm_pack_build_memory *m)
{
    *m = (dm_pack_build_memory){.base_size = DM_PACK_BUILD_MEMORY_BASE_SIZE};
    const uint64_t n = (uint64_t)(b->scene.irradiance_size > 0 ? b->scene.irradiance_size : 0);
    const uint64_t levels = (uint64_t)(b->scene.profile.count > 0 ? b->scene.profile.count : 1);
    if (dm_pack_build_wants(b, "stretch")) {
        m->stretch_size = n * n * (24 * levels + 6);
        m->pack_size += n * n * (8 * levels + 1);
    }
    /* the seam map (RGBA32F, N²) and the thin-part map (RGBA32F, N × 2N): entries the size of the
     * grid, written like the chain */
    if (dm_pack_build_wants(b, "seam")) m->pack_size += n * n * 16;
    if (dm_pack_build_wants(b, "thin")) m->pack_size += n * n * 32 + n * n * 8; /* and thin.half, N/2 × N */
    /* the thin gather at N and N/2: its index (RGBA32F), sites and taps, about 16 taps and 1.1
     * sites (137 bytes) a texel on the head at 1024², counted as 160; where that passes
     * DM_THIN_GATHER_TAPS_MAX texels share taps in blocks (the head at 2048²: 20 M taps), so the
     * taps are counted up to that (8 bytes each); none past DM_THIN_GATHER_SIZE_MAX */
    const uint64_t taps_max = (uint64_t)DM_THIN_GATHER_TAPS_MAX * 8;
    if (dm_pack_build_wants(b, "gather.index") && n <= DM_THIN_GATHER_SIZE_MAX)
        m->pack_size += n * n * 16 + (n * n * 160 < taps_max ? n * n * 160 : taps_max);
    if (dm_pack_build_wants(b, "gather.half.index") && n / 2 <= DM_THIN_GATHER_SIZE_MAX)
        m->pack_size += n * n / 4 * 16 + (n * n / 4 * 160 < taps_max ? n * n / 4 * 160 : taps_max);
    if (dm_pack_build_wants(b, "sss.curvature")) {
        m->curvature_size = n * n * 16;
        m->pack_size += n * n * 4;
    }
    m->write_size = 2 * m->pack_size;
    uint64_t step = m->stretch_size > m->curvature_size ? m->stretch_size : m->curvature_size;
    if (m->write_size > step) step = m->write_size;
    m->total_size = m->base_size + step;
}

dm_result dm_pack_build_memory_check(const dm_pack_build *b, dm_error *err)
{
    dm_pack_build_memory m;
    dm_pack_build_memory_estimate(b, &m);
    char what[160], detail[400], base[32], step[32], pk[32];
    dm_memory_size_text(m.base_size, base, sizeof base);
    dm_memory_size_text(m.stretch_size > m.curvature_size ? m.stretch_size : m.curvature_size, step, sizeof step);
    dm_memory_size_text(m.pack_size, pk, sizeof pk);
    snprintf(what, sizeof what, "%.100s (irradiance_size %d)", b->scene_path, b->scene.irradiance_size);
    if (m.pack_size)
        snprintf(detail, sizeof detail, "%s %s; the grid-sized entries (the chain, the seam and thin-part maps) %s in the pack, held twice while written and verified; maps and bakes %s",
                 m.stretch_size ? "the stretch chain" : "the curvature map", step, pk, base);
    else
        snprintf(detail, sizeof detail, "maps and bakes %s", base);
    return dm_memory_check(m.total_size, what, detail, "lower $.effects.subsurface.irradiance_size in the scene", err);
}
