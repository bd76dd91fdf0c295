/* Screen-space SSS at an albedo edge (issue #29, point 4): a flat plate with an albedo step under
 * uniform light against the profile's own edge, computed independently in double precision
 * (tests/common/edge_plate.h: the line-spread function's integral, with the renderer's
 * pre/post-scatter split of the albedo), at the scene's default 17 taps.
 *
 * Tolerance: the issue's aim is 3 % of the step at every pixel of the row, in every channel; the
 * bounds below hold today's figures (2 % close up, 1 % from the demo's framing out). Before the
 * kernel was fitted to the line-spread function (it was the rank-1 factor of the 2-D product)
 * these were 8.18 / 4.40 / 4.50 % close up and 5.89 / 0.78 / 1.70 % at the demo's framing: the
 * red edge half as wide as the profile's. Other scales and tap counts: bench/ss_edge.c. */
#include <criterion/criterion.h>

#include "../common/edge_plate.h"
#include "host/dm_osmesa.h"

static void expect_edge(double mm_per_px, const double bound[3])
{
    dm_osmesa *ctx = NULL;
    dm_error e = {0};
    cr_assert_eq(dm_osmesa_create(&ctx, &e), DM_OK, "%s", e.detail);
    double err[3];
    char msg[256];
    int rc = edge_plate_error(mm_per_px, 0, err, msg, sizeof msg);
    dm_osmesa_destroy(ctx);
    cr_assert_eq(rc, 0, "%s", msg);
    cr_log_info("ss edge at %s", msg);
    for (int c = 0; c < 3; ++c)
        cr_expect_lt(err[c], bound[c], "%s: channel %d over %.1f %%", msg, c, 100 * bound[c]);
}

/* Close up: 0.1 mm per pixel (the issue's user saw it at 0.075). Before the kernels per size of
 * pixel blue was over the 3 % aim here (3.36 %): the 17 taps' first offset, 0.128 mm, was 1.6 σ of
 * blue's narrowest Gaussian, so the centre tap carried 45 % of blue. Now the near taps sit on
 * whole pixels with the line-spread function's mass over each (core/dm_ssss_kernel.h): 1.29 /
 * 1.68 / 1.34 %, what is left the interpolation between the rows for 0.08 and 0.16 mm per
 * pixel; the bound holds it to 2 %. */
Test(ss_edge, close_up_edge_is_the_profiles_edge)
{
    expect_edge(0.1, (const double[3]){0.02, 0.02, 0.02});
}

/* The demo's framing (`make demo`: assets/scenes/lps.json, 1280x720, fov 30°, the eye 11 units,
 * 550 mm, from the head): the face's vertices lie at eye depths 424 (the nose tip) to ~470 mm,
 * median 456 mm, so 2·456·tan 15° / 720 = 0.34 mm per pixel. */
Test(ss_edge, demo_framing_edge_is_the_profiles_edge)
{
    expect_edge(0.34, (const double[3]){0.01, 0.01, 0.01});
}

/* The issue's close-up (0.075 mm per pixel) and lps-screen-space.json's face (~0.75): between
 * rows of the kernel table, 1.25 / 0.74 / 0.53 % and 0.27 / 0.39 / 0.40 % when the kernels per
 * size of pixel came (3.49 / 5.22 / 6.73 % and 0.54 / 2.96 / 3.52 % before). */
Test(ss_edge, issue_close_up_and_far_framing_edges_are_the_profiles_edge)
{
    expect_edge(0.075, (const double[3]){0.02, 0.02, 0.02});
    expect_edge(0.75, (const double[3]){0.01, 0.01, 0.01});
}
