/* dm_reference_tiles.c — joining texture-space tiles of one dermis-reference run
 * (dm_reference_tiles.h). */
#include "reference/dm_reference_tiles.h"

#include <stdlib.h>
#include <string.h>

#include "image/dm_exr.h"
#include "reference/dm_reference.h"
#include "core/dm_math.h"

/* Everything but the tile index must match; returns the differing parameter's name or NULL. */
static const char *prov_differs(const dm_provenance *a, const dm_provenance *b)
{
    if (strcmp(a->tool, b->tool) || strcmp(a->version, b->version)) return "tool or version";
    if (strcmp(a->input_hash, b->input_hash)) return "input_hash";
    if (a->param_count != b->param_count) return "parameter count";
    for (int i = 0; i < a->param_count; ++i) {
        const dm_param *p = &a->params[i], *q = &b->params[i];
        if (!strcmp(p->name, "tile_index")) continue;
        if (strcmp(p->name, q->name) || p->type != q->type || p->i != q->i || memcmp(&p->d, &q->d, sizeof p->d) ||
            strcmp(p->s, q->s))
            return p->name;
    }
    return NULL;
}

/* Reads every tile and checks they belong together; fills *tiles, *covered. */
static dm_result read_tiles(const char *const *paths, int count, dm_exr_image *img, int64_t *covered, dm_error *err)
{
    unsigned char *seen = NULL;
    int64_t tiles = 0;
    dm_result r = DM_OK;
    for (int f = 0; r == DM_OK && f < count; ++f) {
        if ((r = dm_exr_read(paths[f], &img[f], err)) != DM_OK) break;
        const dm_param *ti = dm_prov_find(&img[f].prov, "tile_index"), *tc = dm_prov_find(&img[f].prov, "tile_count");
        const dm_param *cv = dm_prov_find(&img[f].prov, "covered_texels");
        if (!img[f].has_provenance || strcmp(img[f].prov.tool, "dermis-reference") || !ti || !tc || !cv ||
            !dm_exr_find(&img[f], "A")) {
            r = dm_fail(err, DM_ERR_FORMAT, "%s: not a texture-space tile of dermis-reference", paths[f]);
            break;
        }
        if (f == 0) {
            tiles = tc->i, *covered = cv->i;
            if (tiles < 1 || !(seen = calloc((size_t)tiles + 1, 1))) {
                r = dm_fail(err, DM_ERR_FORMAT, "%s: tile count %lld", paths[f], (long long)tiles);
                break;
            }
        } else {
            const char *d = prov_differs(&img[0].prov, &img[f].prov);
            if (d || img[f].width != img[0].width || img[f].height != img[0].height ||
                img[f].channel_count != img[0].channel_count) {
                r = dm_fail(err, DM_ERR_MISMATCH, "%s: not a tile of the same run as %s (%s differs)", paths[f], paths[0],
                            d ? d : "the image size or channels");
                break;
            }
        }
        if (ti->i < 1 || ti->i > tiles || seen[ti->i]++)
            r = dm_fail(err, DM_ERR_MISMATCH, "%s: tile %lld of %lld %s", paths[f], (long long)ti->i, (long long)tiles,
                        ti->i < 1 || ti->i > tiles ? "is out of range" : "is given twice");
    }
    if (r == DM_OK && count != tiles)
        r = dm_fail(err, DM_ERR_MISMATCH, "%d tiles given, the run has %lld", count, (long long)tiles);
    free(seen);
    return r;
}

dm_result dm_reference_merge_tiles(const char *const *paths, int count, const char *out, int64_t *texels,
                                   dm_error *err)
{
    *texels = 0;
    if (count < 1) return dm_fail(err, DM_ERR_EMPTY, "merge: no tiles");
    dm_exr_image *img = calloc((size_t)count, sizeof *img);
    if (!img) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "merge: %d tiles", count);
    int64_t covered = 0;
    dm_result r = read_tiles(paths, count, img, &covered, err);
    size_t n = r == DM_OK ? (size_t)img[0].width * img[0].height : 0;
    int nch = r == DM_OK ? img[0].channel_count : 0;
    float *planes = r == DM_OK ? calloc(n * (size_t)nch, sizeof *planes) : NULL;
    if (r == DM_OK && !planes) r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "merge: %zu texels", n);
    int64_t merged = 0;
    for (int f = 0; r == DM_OK && f < count; ++f) {
        const float *alpha = dm_exr_find(&img[f], "A");
        for (size_t i = 0; r == DM_OK && i < n; ++i) {
            if (!(alpha[i] > 0.0f)) continue;
            ++merged;
            for (int c = 0; c < nch; ++c) planes[(size_t)c * n + i] = img[f].planes[c][i];
        }
        /* a tile is a result, never repaired: one NaN or infinite value refuses the merge */
        size_t first = 0;
        for (int c = 0; r == DM_OK && c < nch; ++c)
            if (dm_count_nonfinite(img[f].planes[c], n, &first))
                r = dm_fail(err, DM_ERR_NON_FINITE, "%s: channel %s, texel (%zu, %zu) is %g: a tile holds finite values only",
                            paths[f], img[f].names[c], first % (size_t)img[f].width, first / (size_t)img[f].width,
                            (double)img[f].planes[c][first]);
    }
    if (r == DM_OK && merged != covered)
        r = dm_fail(err, DM_ERR_MISMATCH, "the tiles hold %lld texels, the run covers %lld (overlapping tiles?)",
                    (long long)merged, (long long)covered);
    if (r == DM_OK) {
        /* the one-shot run's provenance: tile 1 of 1; JSON keeps no int/double distinction
         * for integral values, so this tool's doubles get their type back */
        dm_provenance prov = img[0].prov;
        static const char *const doubles[] = {"cut_sigma", "spacing_sigma", "wide_texels", "mm_per_unit", "thickness_mm"};
        for (int i = 0; i < prov.param_count; ++i) {
            dm_param *p = &prov.params[i];
            for (size_t d = 0; d < sizeof doubles / sizeof *doubles; ++d)
                if (!strcmp(p->name, doubles[d]) && p->type == DM_PARAM_INT) {
                    p->type = DM_PARAM_DOUBLE;
                    p->d = (double)p->i;
                }
            if (!strcmp(p->name, "tile_index") || !strcmp(p->name, "tile_count")) p->i = 1;
        }
        /* the one-shot run writes R, G, B, A first, then the levels */
        dm_exr_channel ch[4 + 3 * DM_REFERENCE_GAUSSIANS_MAX];
        int k = 0;
        const char *first[4] = {"R", "G", "B", "A"};
        for (int q = 0; q < 4; ++q)
            for (int c = 0; c < nch; ++c)
                if (!strcmp(img[0].names[c], first[q])) ch[k++] = (dm_exr_channel){img[0].names[c], planes + (size_t)c * n, DM_EXR_FLOAT};
        for (int c = 0; c < nch && k < 4 + 3 * DM_REFERENCE_GAUSSIANS_MAX; ++c)
            if (strlen(img[0].names[c]) > 1) ch[k++] = (dm_exr_channel){img[0].names[c], planes + (size_t)c * n, DM_EXR_FLOAT};
        r = dm_exr_write(out, img[0].width, img[0].height, ch, k, &prov, err);
        if (r == DM_OK) *texels = merged;
    }
    for (int f = 0; f < count; ++f) dm_exr_free(&img[f]);
    free(img);
    free(planes);
    return r;
}
