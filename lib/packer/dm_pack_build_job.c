/* dm_pack_build_job.c — what every build step shares (packer/dm_pack_build_impl.h): whether
 * the scene wants an entry, the entry into the writer with its report row, a path's base
 * name, the scene's mesh loaded once. The runner (dm_pack_build.c) and the steps (dm_pack_build_steps.c,
 * dm_pack_build_bake.c) call these; these call neither. */
#include "packer/dm_pack_build_impl.h"

#include <stdio.h>
#include <string.h>

#include "core/dm_cli.h"
#include "mesh/dm_mesh_plausible.h"
#include "pack/dm_pack_needs.h"

bool dm_pack_build_wants(const dm_pack_build *j, const char *entry)
{
    const dm_pack_need *n = dm_pack_need_find(entry);
    return n && dm_pack_entry_applies(entry, &j->scene);
}

dm_result dmpb_add(dm_pack_build *j, const dm_pack_entry *d, const void *data, size_t size, const dm_provenance *prov,
                   const char *source, dm_error *err)
{
    dm_result r = dm_pack_writer_add(&j->w, d, data, size, prov, err);
    if (r != DM_OK) return r;
    if (j->row_count < (int)(sizeof j->rows / sizeof j->rows[0])) {
        dm_pack_build_row *row = &j->rows[j->row_count++];
        snprintf(row->entry, sizeof row->entry, "%s", d->name);
        snprintf(row->source, sizeof row->source, "%s", source);
        row->size = size;
        row->ms = dm_now_ms() - j->step_t0;
    }
    return DM_OK;
}

dm_result dmpb_add_mesh_rgba32f(dm_pack_build *j, const char *entry, int width, int height,
                                const char *const channels[4], const float *texels, const dm_provenance *prov,
                                dm_error *err)
{
    char src[200];
    snprintf(src, sizeof src, "baked from %.150s", dmpb_base_name(j->scene.mesh));
    dm_pack_entry d = dm_pack_texture_entry(entry, DM_TEX_RGBA32F, width, height);
    d.channel_count = 4;
    for (int c = 0; c < 4; ++c) snprintf(d.channels[c], sizeof d.channels[c], "%s", channels[c]);
    return dmpb_add(j, &d, texels, sizeof *texels * 4 * (size_t)width * (size_t)height, prov, src, err);
}

const char *dmpb_base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

dm_result dmpb_ensure_mesh(dm_pack_build *j, dm_error *err)
{
    if (j->mesh_loaded) return DM_OK;
    dm_result r = dm_hash_file_hex(j->scene.mesh, j->mesh_hash, err);
    dm_mesh_load_options o = {.mesh_name = j->scene.mesh_name};
    if (r == DM_OK) r = dm_mesh_load(j->scene.mesh, &o, &j->mesh, err);
    j->mesh_loaded = r == DM_OK;
    j->input_failed = r != DM_OK;
    char plausible[1024];
    if (r == DM_OK && dm_mesh_plausible(&j->mesh, j->scene.mm_per_unit, j->scene.mesh, plausible, sizeof plausible))
        fputs(plausible, stderr);
    return r;
}
