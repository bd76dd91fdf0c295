/* The .dpk pack: a valid pack opens without copies and round-trips through a file, the
 * writer refuses what the reader would, and the mesh comes out in the dermis layout. Bad
 * input: test_pack_bad; several environments: test_pack_env. The packs are small
 * (tests/common/small_pack.h). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../common/small_pack.h"
#include "core/dm_hash.h"
#include "pack/dm_pack.h"
#include "pack/dm_pack_needs.h"
#include "pack/dm_pack_write.h"

/* --- the valid pack ----------------------------------------------------------------- */

Test(pack, valid_pack_opens_without_copies)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    dm_pack pack;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open_memory(buf, size, "t.dpk", &pack, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(pack.entry_count, 7);
    for (int k = 0; k < pack.entry_count; ++k) {
        const dm_pack_entry *e = &pack.entries[k];
        cr_assert((const uint8_t *)e->data >= buf && (const uint8_t *)e->data + e->size <= buf + size, "copied");
        cr_assert_eq((uintptr_t)e->data % 64, 0);
        cr_assert_not_null(e->provenance_json);
    }
    const dm_pack_entry *t = dm_pack_find(&pack, "test.mipmapped");
    cr_assert_not_null(t);
    cr_assert_eq(dm_pack_texture_level_size(t, 0), 4 * 4 * 2 * 8);
    cr_assert_eq(dm_pack_texture_level_size(t, 2), 1 * 1 * 2 * 8);
    cr_assert_eq(dm_pack_texture_level_offset(t, 2), (4 * 4 + 2 * 2) * 2 * 8);
    const dm_pack_entry *vx = dm_pack_find(&pack, "mesh.vertices");
    cr_assert_eq(vx->stride, 48);
    cr_assert_str_eq(vx->attributes[3].name, "tangent");
    dm_scene sc;
    cr_assert_eq(dm_pack_scene(&pack, &sc, &err), DM_OK, "%s", err.detail);
    cr_assert(sc.effects[DM_EFFECT_SPECULAR]);
    dm_pack_close(&pack);
    dm_pack_close(&pack); /* safe twice */
    free(buf);
}

Test(pack, build_is_deterministic_and_file_round_trips)
{
    size_t a_size, b_size;
    uint8_t *a = build_valid(&a_size), *b = build_valid(&b_size);
    cr_assert_eq(a_size, b_size);
    cr_assert_eq(memcmp(a, b, a_size), 0);
    char path[] = "/tmp/dermis-test-pack-XXXXXX";
    int fd = mkstemp(path);
    cr_assert_geq(fd, 0);
    cr_assert_eq(write(fd, a, a_size), (ssize_t)a_size);
    close(fd);
    dm_pack pack;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open(path, &pack, &err), DM_OK, "%s", err.detail);
    cr_assert(pack.mapped);
    cr_assert_eq(memcmp(dm_pack_find(&pack, "env.sh")->data, dm_pack_find(&pack, "env.sh")->data, 108), 0);
    dm_pack_close(&pack);
    unlink(path);
    free(a);
    free(b);
}

Test(pack, writer_write_refuses_an_invalid_pack)
{
    fixture fx = {.nan_in_rho = true};
    dm_pack_writer w;
    dm_pack_writer_init(&w);
    (void)fx;
    dm_provenance p;
    dm_prov_init(&p, "test_pack");
    dm_error err = {0};
    /* a scene that needs lut.beckmann, packed without it */
    add_scene(&w, &p, scene_json);
    add_mesh(&w, &p, false, false);
    char path[] = "/tmp/dermis-test-pack-w-XXXXXX";
    int fd = mkstemp(path);
    close(fd);
    unlink(path);
    cr_assert_neq(dm_pack_writer_write(&w, path, &p, NULL, &err), DM_OK);
    cr_assert(strstr(err.detail, "missing required entry \"lut.beckmann\""), "%s", err.detail);
    cr_assert_neq(access(path, F_OK), 0, "a refused pack was written");
    dm_pack_writer_free(&w);
}

Test(pack, writer_refuses_size_not_matching_format)
{
    dm_pack_writer w;
    dm_pack_writer_init(&w);
    dm_provenance p;
    dm_prov_init(&p, "test_pack");
    dm_error err = {0};
    dm_pack_entry d = dm_pack_texture_entry("lut.beckmann", DM_TEX_R8, 16, 16);
    uint8_t t[255] = {0};
    cr_assert_eq(dm_pack_writer_add(&w, &d, t, sizeof t, &p, &err), DM_ERR_INVALID_ARGUMENT);
    cr_assert(strstr(err.detail, "255 bytes given, expected 256"), "%s", err.detail);
    dm_pack_writer_free(&w);
}

Test(pack, mesh_layout)
{
    size_t size;
    fixture good = {0}, bad = {.no_tangent = true};
    dm_pack pack;
    dm_error err = {0};
    const dm_pack_entry *v, *ix;
    uint8_t *buf = build(&good, &size);
    cr_assert_eq(dm_pack_open_memory(buf, size, "good.dpk", &pack, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_pack_mesh(&pack, &v, &ix, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(v->vertex_count, 3);
    cr_assert_eq(ix->index_count, 3);
    dm_pack_close(&pack);
    free(buf);
    buf = build(&bad, &size);
    expect_refused(buf, size, DM_ERR_FORMAT, "t.dpk: mesh.vertices lacks \"tangent\" at byte 32 with 4 floats");
    free(buf);
}

/* One route for the profile: the "profile" entry must hold the scene's Gaussians. */
