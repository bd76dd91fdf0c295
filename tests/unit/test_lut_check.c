/* Baked LUT files: their texels re-evaluated against the BRDF (core/dm_lut_check.h), and
 * an already-baked file matched to what it was baked for by its provenance. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bake/dm_lut.h"
#include "bake/dm_lut_prov.h"
#include "core/dm_brdf.h"
#include "core/dm_lut_check.h"
#include "image/dm_exr.h"
#include "image/dm_image.h"

/* --- LUT texel re-evaluation --------------------------------------------------------- */

Test(lut_check, baked_tables_pass)
{
    dm_error err = {0};
    dm_beckmann_lut b;
    cr_assert_eq(dm_lut_bake_beckmann(64, 64, 0, 1, &b, &err), DM_OK);
    dm_lut_check c;
    dm_lut_check_beckmann(b.texels, 64, 64, &c);
    cr_assert_eq(c.failures, 0);
    cr_assert_eq(c.samples, 100);
    dm_directional_lut d;
    cr_assert_eq(dm_lut_bake_directional(16, 16, DM_SKIN_F0, 16, 1, &d, &err), DM_OK);
    dm_lut_check_directional(d.rho_dt, 1, 1, 16, 16, DM_SKIN_F0, 16, &c);
    cr_assert_eq(c.failures, 0, "max error %g", c.max_error);
    dm_beckmann_lut_free(&b);
    dm_directional_lut_free(&d);
}

Test(lut_check, corrupted_texel_and_wrong_f0_fail)
{
    dm_error err = {0};
    dm_beckmann_lut b;
    cr_assert_eq(dm_lut_bake_beckmann(64, 64, 0, 1, &b, &err), DM_OK);
    b.texels[63] ^= 0x40; /* corner (63, 0): always sampled */
    dm_lut_check c;
    dm_lut_check_beckmann(b.texels, 64, 64, &c);
    cr_assert_geq(c.failures, 1);
    cr_assert_eq(c.worst_i, 63);
    cr_assert_eq(c.worst_j, 0);
    dm_directional_lut d;
    cr_assert_eq(dm_lut_bake_directional(16, 16, 0.5, 16, 1, &d, &err), DM_OK);
    dm_lut_check_directional(d.rho_dt, 1, 1, 16, 16, DM_SKIN_F0, 16, &c);
    cr_assert_gt(c.failures, 50);
    dm_beckmann_lut_free(&b);
    dm_directional_lut_free(&d);
}

/* --- already-baked LUT files: provenance matching ----------------------------------- */

Test(lut_prov, matching_and_mismatching_files)
{
    dm_provenance want, have;
    dm_error err = {0};
    dm_lut_prov_directional(&want, "dermis-pack", "rho_dt", 64, 64, DM_SKIN_F0, 32);
    dm_lut_prov_directional(&have, "dermis-bake-lut", "rho_dt", 64, 64, DM_SKIN_F0, 32);
    cr_assert_eq(dm_lut_prov_match(&have, &want, "a.exr", &err), DM_OK, "%s", err.detail); /* tool may differ */
    dm_lut_prov_directional(&have, "dermis-bake-lut", "rho_dt", 64, 64, DM_SKIN_F0, 48);
    cr_assert_eq(dm_lut_prov_match(&have, &want, "a.exr", &err), DM_ERR_MISMATCH);
    cr_assert(strstr(err.detail, "a.exr: nodes is 48, expected 32"), "%s", err.detail);
    dm_lut_prov_directional(&have, "dermis-bake-lut", "env_brdf", 64, 64, DM_SKIN_F0, 32);
    cr_assert_eq(dm_lut_prov_match(&have, &want, "a.exr", &err), DM_ERR_MISMATCH);
    cr_assert(strstr(err.detail, "table is \"env_brdf\", expected \"rho_dt\""), "%s", err.detail);
    dm_lut_prov_directional(&have, "dermis-bake-lut", "rho_dt", 64, 64, DM_SKIN_F0, 32);
    snprintf(have.version, sizeof have.version, "0.0.1");
    cr_assert_eq(dm_lut_prov_match(&have, &want, "a.exr", &err), DM_ERR_MISMATCH);
    cr_assert(strstr(err.detail, "baked by dermis 0.0.1"), "%s", err.detail);
}

Test(lut_prov, provenance_survives_png_and_exr_files)
{
    dm_error err = {0};
    dm_beckmann_lut b;
    cr_assert_eq(dm_lut_bake_beckmann(32, 32, 0, 1, &b, &err), DM_OK);
    dm_provenance p;
    dm_lut_prov_beckmann(&p, "dermis-bake-lut", 32, 32);
    dm_image img = {.width = 32, .height = 32, .channels = 1, .type = DM_PIXEL_U8, .pixels = b.texels};
    char png[64];
    snprintf(png, sizeof png, "/tmp/dermis-test-lut-%ld.png", (long)getpid());
    cr_assert_eq(dm_png_write(png, &img, &p, &err), DM_OK, "%s", err.detail);
    dm_image back;
    cr_assert_eq(dm_image_read(png, DM_PIXEL_U8, &back, &err), DM_OK, "%s", err.detail);
    cr_assert(back.has_provenance);
    cr_assert_eq(dm_lut_prov_match(&back.prov, &p, png, &err), DM_OK, "%s", err.detail);
    dm_lut_check c;
    dm_lut_check_beckmann(back.pixels, 32, 32, &c);
    cr_assert_eq(c.failures, 0);
    dm_image_free(&back);
    dm_beckmann_lut_free(&b);
    unlink(png);
}
