/* dm_golden.h — golden-image comparison for render tests (test-only, header-only).
 *
 * golden_check("name", w, h, rgba8, tol) compares an 8-bit RGBA image (bottom-up) with
 * $DERMIS_GOLDEN_DIR/name.png (default tests/render/golden, relative to the repository
 * root where `make test` runs). It passes when the largest per-channel difference is at
 * most tol->max_abs and the mean is at most tol->mean_abs (in 8-bit steps). With
 * DERMIS_UPDATE_GOLDEN=1 it writes the image as the new golden instead and passes.
 * Reading and writing go through image/dm_image.h (tests link the bake library).
 */
#ifndef DM_GOLDEN_H
#define DM_GOLDEN_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/dm_image.h"
#include "core/dm_prov.h"

typedef struct golden_tolerance {
    int max_abs;     /* 8-bit steps */
    double mean_abs; /* 8-bit steps */
} golden_tolerance;

/* Returns 1 on pass; on failure fills msg. */
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-truncation" /* messages may be cut short: fine */
#endif
static inline int golden_check(const char *name, int w, int h, const uint8_t *rgba, golden_tolerance tol, char *msg,
                               size_t msg_size)
{
    const char *dir = getenv("DERMIS_GOLDEN_DIR");
    char path[768];
    snprintf(path, sizeof path, "%s/%s.png", dir && *dir ? dir : "tests/render/golden", name);
    const char *update = getenv("DERMIS_UPDATE_GOLDEN");
    dm_error err = {0};
    if (update && strcmp(update, "1") == 0) {
        dm_provenance prov;
        dm_prov_init(&prov, "golden");
        dm_prov_add_string(&prov, "test", name);
        dm_image img = {.width = w, .height = h, .channels = 4, .type = DM_PIXEL_U8, .pixels = (void *)rgba};
        if (dm_png_write(path, &img, &prov, &err) != DM_OK) {
            snprintf(msg, msg_size, "update: %s", err.detail);
            return 0;
        }
        fprintf(stderr, "golden: updated %s\n", path);
        return 1;
    }
    dm_image g = {0};
    if (dm_image_read(path, DM_PIXEL_U8, &g, &err) != DM_OK) {
        dm_image_free(&g);
        snprintf(msg, msg_size, "%s (run with DERMIS_UPDATE_GOLDEN=1 to create it)", err.detail);
        return 0;
    }
    if (g.width != w || g.height != h || g.channels != 4) {
        snprintf(msg, msg_size, "%s: %dx%dx%d, rendered %dx%dx4", path, g.width, g.height, g.channels, w, h);
        dm_image_free(&g);
        return 0;
    }
    const uint8_t *ref = g.pixels;
    int worst = 0;
    size_t worst_at = 0;
    double sum = 0;
    size_t n = (size_t)w * h * 4;
    for (size_t i = 0; i < n; ++i) {
        int d = abs((int)rgba[i] - (int)ref[i]);
        sum += d;
        if (d > worst) worst = d, worst_at = i;
    }
    dm_image_free(&g);
    double mean = sum / (double)n;
    if (worst > tol.max_abs || mean > tol.mean_abs) {
        snprintf(msg, msg_size, "%s: max difference %d at pixel (%zu, %zu) channel %zu (allowed %d), mean %.3f (allowed %.3f)",
                 path, worst, (worst_at / 4) % (size_t)w, (worst_at / 4) / (size_t)w, worst_at % 4, tol.max_abs, mean,
                 tol.mean_abs);
        return 0;
    }
    return 1;
}
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#endif
