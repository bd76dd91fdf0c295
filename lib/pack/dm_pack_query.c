/* dm_pack_query.c — what a caller asks of an opened pack (pack/dm_pack_query.h): entries by
 * name, the mesh in the dermis layout, the scene kept while verifying. */
#include "pack/dm_pack_query.h"

#include <stdint.h>
#include <string.h>

const dm_pack_entry *dm_pack_find(const dm_pack *pack, const char *name)
{
    for (int k = 0; k < pack->entry_count; ++k)
        if (strcmp(pack->entries[k].name, name) == 0) return &pack->entries[k];
    return NULL;
}

dm_result dm_pack_find_texture(const dm_pack *pack, const char *name, const dm_pack_entry **out, dm_error *err)
{
    const dm_pack_entry *e = dm_pack_find(pack, name);
    *out = NULL;
    if (!e) return DM_OK;
    if (e->kind != DM_PACK_TEXTURE || e->levels != 1 || e->layers != 1)
        return dm_fail(err, DM_ERR_FORMAT, "%s: entry \"%s\": expected a texture of 1 level and 1 layer", pack->what,
                       name);
    *out = e;
    return DM_OK;
}

dm_result dm_pack_env_level_m(const dm_pack *pack, const dm_pack_entry *e, float *m, dm_error *err)
{
    if (e->layer_value_count != e->layers)
        return dm_fail(err, DM_ERR_FORMAT,
                       "%s: %s has no \"layer_values\" (the Beckmann m of each of its %d layers); pack the scene "
                       "again with this dermis-pack",
                       pack->what, e->name, e->layers);
    for (int k = 0; k < e->layers; ++k) m[k] = e->layer_values[k];
    return DM_OK;
}

/* The scene entry was parsed while the pack was verified (dm_pack_verify.c keeps it): a copy,
 * not a second parse. */
dm_result dm_pack_scene(const dm_pack *pack, dm_scene *scene, dm_error *err)
{
    const dm_pack_entry *e = dm_pack_find(pack, "scene");
    if (!e || e->kind != DM_PACK_SCENE || !e->data || !pack->scene)
        return dm_fail(err, DM_ERR_FORMAT, "%s: no scene entry, expected one", pack->what);
    *scene = *pack->scene;
    return DM_OK;
}

dm_result dm_pack_mesh(const dm_pack *pack, const dm_pack_entry **vertices, const dm_pack_entry **indices,
                       dm_error *err)
{
    const dm_pack_entry *v = dm_pack_find(pack, "mesh.vertices"), *ix = dm_pack_find(pack, "mesh.indices");
    *vertices = *indices = NULL;
    if (!v || !ix) return dm_fail(err, DM_ERR_EMPTY, "%s: no mesh.vertices/mesh.indices entries", pack->what);
    if (v->stride != DM_PACK_VERTEX_STRIDE)
        return dm_fail(err, DM_ERR_FORMAT, "%s: mesh.vertices stride %d, expected the dermis layout's %d",
                       pack->what, v->stride, DM_PACK_VERTEX_STRIDE);
    static const struct {
        const char *name;
        int offset, components;
    } layout[] = {{"position", DM_PACK_VERTEX_POSITION, 3},
                  {"normal", DM_PACK_VERTEX_NORMAL, 3},
                  {"uv", DM_PACK_VERTEX_UV, 2},
                  {"tangent", DM_PACK_VERTEX_TANGENT, 4}};
    for (size_t k = 0; k < sizeof layout / sizeof layout[0]; ++k) {
        int found = 0;
        for (int i = 0; i < v->attribute_count; ++i)
            if (!strcmp(v->attributes[i].name, layout[k].name) && v->attributes[i].offset == layout[k].offset &&
                v->attributes[i].components == layout[k].components)
                found = 1;
        if (!found)
            return dm_fail(err, DM_ERR_FORMAT, "%s: mesh.vertices lacks \"%s\" at byte %d with %d floats", pack->what,
                           layout[k].name, layout[k].offset, layout[k].components);
    }
    if (v->vertex_count > INT32_MAX || ix->index_count > INT32_MAX)
        return dm_fail(err, DM_ERR_RANGE, "%s: mesh of %lld vertices, %lld indices is too large", pack->what,
                       (long long)v->vertex_count, (long long)ix->index_count);
    *vertices = v;
    *indices = ix;
    return DM_OK;
}
