/* The last line of defence (issue #31 point 1): a picture holding NaN or infinite values is
 * never written. dm_renderer_check_finite refuses a frame whose view holds them, naming the
 * view and the targets where they arose; dm_render_write_exr refuses such a buffer and
 * writes nothing. Assets here bypass the pack reader (its checks would refuse these). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/dm_math.h"
#include "core/dm_prov.h"
#include "host/dm_osmesa.h"
#include "render/dm_render.h"
#include "render/dm_render_image.h"
#include "render/dm_render_synth.h"

#include "../common/tmpdir.h"

static dm_result frame_check(dm_synth *s, dm_error *err)
{
    dm_render_desc d = {.width = 48, .height = 32, .irradiance_size = 64, .shadow_size = 64};
    dm_renderer *r = NULL;
    cr_assert_eq(dm_renderer_create(&s->assets, &d, &r, err), DM_OK, "%s", err->detail);
    cr_assert_eq(dm_render_frame(r, &(dm_frame_options){0}, err), DM_OK, "%s", err->detail);
    dm_result rc = dm_renderer_check_finite(r, err);
    dm_renderer_destroy(r);
    return rc;
}

Test(render_finite, nan_in_the_view_is_refused_by_name, .timeout = 120)
{
    dm_osmesa *ctx = NULL;
    dm_synth *s = NULL;
    dm_error err = {0};
    dm_synth_options so = {.sphere_segments = 24, .sphere_rings = 12, .stretch_size = 32, .beckmann_size = 32,
                           .directional_size = 8};
    cr_assert_eq(dm_osmesa_create(&ctx, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(dm_synth_create(&so, &s, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(frame_check(s, &err), DM_OK, "the synthetic sphere: %s", err.detail);
    /* zero normals (what the pack reader refuses): normalize(0) is NaN on the whole head */
    const int n = s->assets.vertex_count, at = DM_PACK_VERTEX_NORMAL / 4;
    float *normals = malloc((size_t)n * 3 * sizeof *normals);
    for (int i = 0; i < n; ++i) {
        memcpy(normals + 3 * i, s->vertices + (size_t)i * DM_VERTEX_FLOATS + at, 3 * sizeof(float));
        memset(s->vertices + (size_t)i * DM_VERTEX_FLOATS + at, 0, 3 * sizeof(float));
    }
    cr_assert_eq(frame_check(s, &err), DM_ERR_NON_FINITE, "%s", err.detail);
    cr_expect(strstr(err.detail, "view final: "), "%s", err.detail);
    cr_expect(strstr(err.detail, "values are NaN or infinite"), "%s", err.detail);
    cr_expect(strstr(err.detail, "targets holding such values: ") && strstr(err.detail, "screen ("), "%s",
              err.detail);
    cr_expect(strstr(err.detail, "no picture written"), "%s", err.detail);
    for (int i = 0; i < n; ++i)
        memcpy(s->vertices + (size_t)i * DM_VERTEX_FLOATS + at, normals + 3 * i, 3 * sizeof(float));
    free(normals);
    cr_assert_eq(frame_check(s, &err), DM_OK, "normals back: %s", err.detail);
    /* infinite too: a rho_dt table of -1e38 (energy conservation: 1 - rho_s rho_dt overflows) */
    for (int i = 0; i < s->assets.rho_dt.width * s->assets.rho_dt.height; ++i) s->rho_dt[i] = -1e38f;
    cr_expect_eq(frame_check(s, &err), DM_ERR_NON_FINITE, "%s", err.detail);
    dm_synth_free(s);
    dm_osmesa_destroy(ctx);
}

Test(render_finite, exr_writer_refuses_nan_and_writes_nothing)
{
    char dir[256], path[512];
    cr_assert(test_tmpdir(dir, sizeof dir));
    snprintf(path, sizeof path, "%s/out.exr", dir);
    dm_provenance prov;
    dm_prov_init(&prov, "test_render_finite");
    float px[4 * 3 * 2];
    for (size_t i = 0; i < sizeof px / sizeof px[0]; ++i) px[i] = 0.5f;
    dm_error err = {0};
    cr_assert_eq(dm_render_write_exr(path, 3, 2, px, &prov, &err), DM_OK, "%s", err.detail);
    cr_assert_eq(unlink(path), 0);
    px[4 * 4 + 1] = NAN; /* pixel (1, 1) of the bottom-up buffer: the file's top row */
    px[4 * 5 + 2] = INFINITY;
    cr_assert_eq(dm_render_write_exr(path, 3, 2, px, &prov, &err), DM_ERR_NON_FINITE);
    cr_expect(strstr(err.detail, "out.exr: 2 of 24 values are NaN or infinite, the first at pixel (1, 0) channel 1; "
                                 "nothing written"),
              "%s", err.detail);
    cr_expect_neq(access(path, F_OK), 0, "%s was written", path);
    cr_expect_eq(test_count_files(dir, NULL), 0, "a temporary file was left in %s", dir);
    size_t first = 0;
    cr_expect_eq(dm_count_nonfinite(px, 24, &first), 2);
    cr_expect_eq(first, 17);
    cr_expect_eq(dm_count_nonfinite(px, 16, &first), 0);
    cr_expect_eq(first, 16);
}
