/* The .dpk pack's bad input: every kind is refused with a message naming the file, the
 * field and what was expected, never a crash. The packs are small (a few KiB,
 * tests/common/small_pack.h) so that every truncation and every bit flip can be tried in
 * well under a second. */
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

/* --- bad input: one test per kind ---------------------------------------------------- */

Test(pack_bad, truncated_at_every_length)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    for (size_t n = 0; n < size; ++n) expect_refused(buf, n, DM_OK, NULL);
    free(buf);
}

Test(pack_bad, truncated_with_a_consistent_header)
{
    /* file_size patched to the truncated length, checksum recomputed: the blob bounds fail */
    size_t size;
    uint8_t *buf = build_valid(&size);
    size_t n = size - 100;
    for (int k = 0; k < 8; ++k) buf[16 + k] = (uint8_t)((uint64_t)n >> (8 * k));
    char *m = manifest_of(buf);
    set_manifest(buf, m);
    free(m);
    expect_refused(buf, n, DM_ERR_FORMAT, "outside the blob area");
    free(buf);
}

Test(pack_bad, flipped_bit_anywhere)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    int tried = 0;
    for (size_t byte = 0; byte < size; ++byte)
        for (int bit = 0; bit < 8; ++bit, ++tried) {
            buf[byte] ^= (uint8_t)(1u << bit);
            expect_refused(buf, size, DM_OK, NULL);
            buf[byte] ^= (uint8_t)(1u << bit);
        }
    cr_assert_eq(tried, (int)size * 8);
    free(buf);
}

Test(pack_bad, wrong_magic)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    memcpy(buf, "PK\x03\x04zipx", 8);
    expect_refused(buf, size, DM_ERR_FORMAT, "magic 50 4b 03 04");
    free(buf);
}

Test(pack_bad, wrong_version)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    buf[8] = 2;
    expect_refused(buf, size, DM_ERR_UNSUPPORTED, "version 2, expected 1");
    free(buf);
}

Test(pack_bad, unknown_flags)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    buf[12] = 1;
    expect_refused(buf, size, DM_ERR_UNSUPPORTED, "flags 0x00000001");
    free(buf);
}

Test(pack_bad, header_checksum)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    buf[60] ^= 0x10;
    expect_refused(buf, size, DM_ERR_CHECKSUM, "header+manifest checksum");
    free(buf);
}

Test(pack_bad, blob_checksum)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    buf[size - 1] ^= 0x01; /* inside the last blob (env.sh) */
    expect_refused(buf, size, DM_ERR_CHECKSUM, "entry \"env.sh\": checksum");
    free(buf);
}

Test(pack_bad, offset_past_the_end)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    char *m = manifest_of(buf), *e = strstr(m, "\"name\":\t\"env.sh\"");
    cr_assert(e);
    long off;
    cr_assert_eq(sscanf(strstr(e, "\"offset\":") + 9, "%ld", &off), 1);
    char from[32], to[32];
    snprintf(from, sizeof from, "%ld", off);
    long far = 1;
    for (size_t k = 0; k < strlen(from); ++k) far *= 10;
    far = (far - 1) / 64 * 64; /* aligned, as many digits, past the end of this small pack */
    cr_assert_gt(far, (long)size);
    snprintf(to, sizeof to, "%ld", far);
    edit_manifest(buf, "\"name\":\t\"env.sh\"", from, to);
    expect_refused(buf, size, DM_ERR_FORMAT, "outside the blob area");
    free(m);
    free(buf);
}

Test(pack_bad, overlapping_blobs)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    char *m = manifest_of(buf);
    long a, b;
    cr_assert_eq(sscanf(strstr(strstr(m, "\"name\":\t\"mesh.indices\""), "\"offset\":") + 9, "%ld", &a), 1);
    cr_assert_eq(sscanf(strstr(strstr(m, "\"name\":\t\"env.sh\""), "\"offset\":") + 9, "%ld", &b), 1);
    char from[32], to[32];
    snprintf(from, sizeof from, "%ld", b);
    snprintf(to, sizeof to, "%ld", a);
    edit_manifest(buf, "\"name\":\t\"env.sh\"", from, to);
    expect_refused(buf, size, DM_ERR_FORMAT, "overlap");
    free(m);
    free(buf);
}

Test(pack_bad, misaligned_offset)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    char *m = manifest_of(buf);
    long b;
    cr_assert_eq(sscanf(strstr(strstr(m, "\"name\":\t\"env.sh\""), "\"offset\":") + 9, "%ld", &b), 1);
    char from[32], to[32];
    snprintf(from, sizeof from, "%ld", b);
    snprintf(to, sizeof to, "%ld", b + 4);
    edit_manifest(buf, "\"name\":\t\"env.sh\"", from, to);
    expect_refused(buf, size, DM_ERR_FORMAT, "expected a multiple of 64");
    free(m);
    free(buf);
}

Test(pack_bad, malformed_manifest_json)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    set_manifest(buf, "{\"format\": \"dermis-pack\", \"entries\": [");
    expect_refused(buf, size, DM_ERR_FORMAT, "manifest is not valid JSON");
    free(buf);
}

Test(pack_bad, manifest_unknown_key)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    edit_manifest(buf, "\"name\":\t\"lut.rho_dt\"", "\"layers\"", "\"layerz\"");
    expect_refused(buf, size, DM_ERR_FORMAT, "$.entries[2].layerz: unknown key");
    free(buf);
}

Test(pack_bad, manifest_unknown_kind)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    edit_manifest(buf, "\"name\":\t\"env.sh\"", "\"kind\":\t\"env.sh\"", "\"kind\":\t\"env.xx\"");
    expect_refused(buf, size, DM_ERR_FORMAT, "\"env.xx\" is not one of texture");
    free(buf);
}

Test(pack_bad, manifest_unknown_format)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    edit_manifest(buf, "\"name\":\t\"lut.rho_dt\"", "\"r32f\"", "\"r64f\"");
    expect_refused(buf, size, DM_ERR_FORMAT, "$.entries[2].format: \"r64f\"");
    free(buf);
}

Test(pack_bad, manifest_missing_field)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    edit_manifest(buf, "\"name\":\t\"lut.rho_dt\"", "\"width\"", "\"widtx\"");
    expect_refused(buf, size, DM_ERR_FORMAT, "widtx: unknown key");
    free(buf);
}

Test(pack_bad, size_against_format)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    edit_manifest(buf, "\"name\":\t\"lut.rho_dt\"", "\"width\":\t8", "\"width\":\t9");
    expect_refused(buf, size, DM_ERR_FORMAT, "size 256 bytes, expected 288 for its format");
    free(buf);
}

Test(pack_bad, duplicate_entry_name)
{
    size_t size;
    uint8_t *buf = build_valid(&size);
    edit_manifest(buf, "\"offset\"", "\"name\":\t\"env.sh\"", "\"name\":\t\"scene\"");
    expect_refused(buf, size, DM_ERR_FORMAT, "named \"scene\"");
    free(buf);
}

Test(pack_bad, missing_required_entry)
{
    fixture fx = {.skip_beckmann = true};
    size_t size;
    uint8_t *buf = build(&fx, &size);
    expect_refused(buf, size, DM_ERR_FORMAT, "missing required entry \"lut.beckmann\"");
    free(buf);
}

Test(pack_bad, required_entry_of_the_wrong_format)
{
    fixture fx = {.beckmann_as_float = true};
    size_t size;
    uint8_t *buf = build(&fx, &size);
    expect_refused(buf, size, DM_ERR_FORMAT, "\"lut.beckmann\" is texture r32f, expected texture r8");
    free(buf);
}

/* The one reader of the mesh entries' layout (renderer and reference alike): a pack whose
 * mesh.vertices lacks it is refused on open. */

Test(pack_bad, profile_entry_differs_from_the_scene)
{
    size_t size;
    fixture same = {.profile = 1}, other = {.profile = 2};
    uint8_t *buf = build(&same, &size);
    dm_pack pack;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open_memory(buf, size, "same.dpk", &pack, &err), DM_OK, "%s", err.detail);
    cr_assert_not_null(pack.profile);
    cr_assert_eq(pack.profile->count, 6);
    dm_pack_close(&pack);
    free(buf);
    buf = build(&other, &size);
    expect_refused(buf, size, DM_ERR_MISMATCH, "entry \"profile\" ('gems3-skin', 6 Gaussians) differs from the scene's profile");
    free(buf);
}

Test(pack_bad, nan_in_a_texture)
{
    fixture fx = {.nan_in_rho = true};
    size_t size;
    uint8_t *buf = build(&fx, &size);
    expect_refused(buf, size, DM_ERR_NON_FINITE, "entry \"lut.rho_dt\": texel (5, 3) of level 0 layer 0");
    free(buf);
}

Test(pack_bad, index_out_of_range)
{
    fixture fx = {.bad_index = true};
    size_t size;
    uint8_t *buf = build(&fx, &size);
    expect_refused(buf, size, DM_ERR_RANGE, "index 2 is 7, expected < 3");
    free(buf);
}

Test(pack_bad, empty_and_tiny_files)
{
    static const uint8_t z[64] = {0};
    expect_refused(z, 0, DM_ERR_FORMAT, "0 bytes, expected at least the 64-byte header");
    expect_refused(z, 64, DM_ERR_FORMAT, "magic");
}

Test(pack_bad, not_a_file)
{
    dm_pack pack;
    dm_error err = {0};
    cr_assert_eq(dm_pack_open("/nonexistent/x.dpk", &pack, &err), DM_ERR_FILE_OPEN);
    cr_assert(strstr(err.detail, "/nonexistent/x.dpk"));
    cr_assert_eq(dm_pack_open("/tmp", &pack, &err), DM_ERR_FILE_OPEN);
}
