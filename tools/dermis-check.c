/* dermis-check — validates packs, LUTs, stretch maps, profiles and scenes.
 * For each file: detect its type → run every check → print "FILE: ok" or every failure. */
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cJSON.h>

#include "image/dm_exr.h"
#include "image/dm_image.h"
#include "core/dm_cli.h"
#include "core/dm_brdf.h"
#include "pack/dm_format_version.h"
#include "core/dm_input.h"
#include "core/dm_lut_check.h"
#include "pack/dm_pack.h"
#include "pack/dm_pack_needs.h"
#include "pack/dm_pack_semantic.h"
#include "core/dm_profile.h"
#include "core/dm_prov.h"
#include "core/dm_scene.h"
#include "core/dm_version.h"

enum { CHECK_OK = 0, CHECK_FAILED = 1, CHECK_USAGE = 2, MAX_FAILURES = 32 };

static void usage(FILE *f)
{
    fprintf(f, "Usage: dermis-check [--json | --format-version] [-v] [--quiet] [--assets DIR] FILE...\n"
               "Validates dermis files: packs (.dpk), Beckmann LUT PNGs, rho_dt / env-BRDF / stretch EXRs,\n"
               "profile and scene JSONs: structure, ranges, finiteness, provenance, cross-consistency,\n"
               "and a sample of LUT texels re-evaluated against the analytic functions.\n"
               "\n"
               "Options:\n"
               "  --json         one JSON object on stdout: {\"files\": [{\"file\", \"type\", \"ok\", \"failures\"}]}\n"
               "  --format-version  only print each pack's/scene's format, version and whether this dermis reads it\n"
               "  --assets DIR   where scenes' paths missing beside the scene are looked for, before\n"
               "                 DERMIS_ASSETS and the build's default (repeatable, up to 8)\n"
               "  -v, --verbose  also say what was checked\n"
               "  --quiet        print failures only\n"
               "  -h, --help     this text (--version: the dermis version)\n"
               "\n"
               "Exit codes: 0 every file passed, 1 a check failed (or a version not read), 2 usage (or no version).\n");
}

typedef struct result {
    const char *file;
    const char *type;
    int count;
    char failures[MAX_FAILURES][1024];
    int notes;
    char note[16][256];
    char made_by[160]; /* "TOOL VERSION" from the file's provenance, or "" */
} result;

static void fail(result *r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static void fail(result *r, const char *fmt, ...)
{
    if (r->count >= MAX_FAILURES) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->failures[r->count++], sizeof r->failures[0], fmt, ap);
    va_end(ap);
}

static void note(result *r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static void note(result *r, const char *fmt, ...)
{
    if (r->notes >= 16) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->note[r->notes++], sizeof r->note[0], fmt, ap);
    va_end(ap);
}

static bool ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

/* --- provenance --------------------------------------------------------------------- */

static void check_prov(result *r, const dm_provenance *p, bool present, const char *where)
{
    if (!present) {
        fail(r, "%s: no dermis provenance, expected the tool, version and parameters that made it", where);
        return;
    }
    if (!p->tool[0] || !p->version[0]) fail(r, "%s: provenance without tool or version", where);
    if (!r->made_by[0]) snprintf(r->made_by, sizeof r->made_by, "%s %s", p->tool, p->version);
}

/* A file of another dermis tool (an environment bake, the exact Beckmann table, a render,
 * a reference): its provenance names the tool, and every value must be finite. */
static void check_other(result *r, const char *file, const dm_provenance *p, bool present, float *const *planes,
                        int plane_count, size_t plane_size)
{
    check_prov(r, p, present, file);
    size_t bad = 0;
    for (int c = 0; c < plane_count; ++c)
        for (size_t i = 0; planes && i < plane_size; ++i) bad += !isfinite(planes[c][i]);
    if (bad) fail(r, "%s: %zu NaN or infinite values, expected finite", file, bad);
    if (present) note(r, "%s: %d channels, every value finite", file, plane_count);
}

static double prov_num(const dm_provenance *p, const char *name, double fallback)
{
    const dm_param *q = dm_prov_find(p, name);
    return q && q->type != DM_PARAM_STRING ? q->d : fallback;
}

/* --- LUT samples (core/dm_lut_check.h) ---------------------------------------------- */

static void report_lut(result *r, const char *where, const dm_lut_check *c)
{
    if (c->failures)
        fail(r, "%s: %d of %d sampled texels differ from the analytic function; worst at texel (%d, %d): %.9g, "
                "expected %.9g",
             where, c->failures, c->samples, c->worst_i, c->worst_j, c->worst_value, c->worst_expected);
    else
        note(r, "%s: %d texels re-evaluated, max |error| %.3g", where, c->samples, c->max_error);
}

/* --- profiles ----------------------------------------------------------------------- */

/* A profile JSON, parsed once by the caller (root: NULL when the text is not JSON, which
 * dm_profile_from_cjson then reports). */
static void check_profile_json(result *r, const char *file, const cJSON *root)
{
    dm_error err = {0};
    dm_profile p;
    if (dm_profile_from_cjson(root, file, &p, &err) != DM_OK) { /* its ranges: dm_profile_validate */
        fail(r, "%s", err.detail);
        return;
    }
    const cJSON *pv = cJSON_GetObjectItemCaseSensitive(root, "provenance");
    dm_provenance prov;
    bool ok = pv && dm_prov_from_cjson(&prov, pv, file, &err) == DM_OK;
    check_prov(r, &prov, ok, file);
    note(r, "%s: %d Gaussians", p.name, p.count);
}

/* --assets folders, in order (set once by main). */
static const char *g_assets[8];
static int g_asset_count;

/* A scene: read from its parsed root when the file is one whole JSON value (`text`, `size`
 * bytes), else (NUL bytes, trailing text, invalid JSON) by the scene reader, whose refusal
 * names the line and column; then every file it names must exist. */
static void check_scene_json(result *r, const char *file, const cJSON *root, const char *text, size_t size, bool whole)
{
    dm_error err = {0};
    dm_scene *s = malloc(sizeof *s);
    if (!s) {
        fail(r, "%s: out of memory", file);
        return;
    }
    dm_result got = whole ? dm_scene_from_cjson(root, text, size, file, g_assets, g_asset_count, s, &err)
                          : dm_scene_read_assets(file, g_assets, g_asset_count, s, &err);
    if (got != DM_OK) {
        fail(r, "%s", err.detail);
    } else {
        const struct { const char *key, *path; } files[] = {
            {"$.mesh.path", s->mesh},           {"$.material.albedo", s->albedo},
            {"$.material.normal_map", s->normal_map}, {"$.material.specular_map", s->specular_map},
            {"$.material.roughness_map", s->roughness_map}, {"$.environment.path", s->environment}};
        for (size_t k = 0; k < sizeof files / sizeof files[0]; ++k) {
            struct stat st;
            if (files[k].path[0] && (stat(files[k].path, &st) != 0 || !S_ISREG(st.st_mode)))
                fail(r, "%s: %s: \"%s\" does not exist, expected a file", file, files[k].key, files[k].path);
        }
    }
    free(s);
}

/* --- stretch ------------------------------------------------------------------------ */

/* Stretch planes (UV units per mm) must be in the pack's range at every texel
 * (dm_pack_stretch_ok, the rule the pack reader applies to its stretch entry): gutters are filled. */
static void check_stretch_plane(result *r, const char *where, const float *v, int w, int h)
{
    int64_t bad = 0, first = -1;
    for (int64_t i = 0; i < (int64_t)w * h; ++i) {
        if (!dm_pack_stretch_ok(v[i])) {
            if (first < 0) first = i;
            ++bad;
        }
    }
    if (bad)
        fail(r, "%s: %" PRId64 " texels outside (0, %g] UV units per mm, first at (%d, %d) = %g", where, bad,
             DM_PACK_STRETCH_MAX_PER_MM, (int)(first % w), (int)(first / w), (double)v[first]);
}

static void check_stretch_exr(result *r, const char *file, const dm_exr_image *img)
{
    int levels = 0;
    char name[64];
    for (;; ++levels) {
        snprintf(name, sizeof name, "stretch%d.u", levels);
        if (!dm_exr_find(img, name)) break;
    }
    if (levels == 0) fail(r, "%s: no channel stretch0.u, expected stretch<k>.u/.v levels", file);
    for (int k = 0; k < levels; ++k) {
        for (int a = 0; a < 2; ++a) {
            snprintf(name, sizeof name, "stretch%d.%c", k, a ? 'v' : 'u');
            const float *p = dm_exr_find(img, name);
            char where[600];
            snprintf(where, sizeof where, "%s: channel %s", file, name);
            if (!p)
                fail(r, "%s: missing, expected it beside stretch%d.u", where, k);
            else
                check_stretch_plane(r, where, p, img->width, img->height);
        }
    }
    const float *mask = dm_exr_find(img, "mask");
    if (!mask) {
        fail(r, "%s: no channel \"mask\", expected the chart coverage mask", file);
    } else {
        int64_t bad = 0;
        for (int64_t i = 0; i < (int64_t)img->width * img->height; ++i)
            if (!(mask[i] >= 0.0f && mask[i] <= 1.0f)) ++bad;
        if (bad) fail(r, "%s: channel mask: %" PRId64 " texels outside [0, 1]", file, bad);
    }
    for (int c = 0; c < img->channel_count; ++c) {
        int k;
        char ax;
        if (strcmp(img->names[c], "mask") != 0 &&
            !(sscanf(img->names[c], "stretch%d.%c", &k, &ax) == 2 && k >= 0 && k < levels && (ax == 'u' || ax == 'v')))
            fail(r, "%s: unexpected channel \"%s\"", file, img->names[c]);
    }
    check_prov(r, &img->prov, img->has_provenance, file);
    if (img->has_provenance) {
        double mm = prov_num(&img->prov, "mm_per_unit", NAN);
        if (!(mm > 0.0) || !isfinite(mm)) fail(r, "%s: provenance mm_per_unit is %g, expected a value > 0", file, mm);
        if (!img->prov.input_hash[0]) fail(r, "%s: provenance has no input_hash (the mesh's), expected one", file);
    }
    note(r, "%d stretch levels, %dx%d", levels, img->width, img->height);
}

/* --- LUT files ---------------------------------------------------------------------- */

static void check_beckmann_png(result *r, const char *file)
{
    dm_error err = {0};
    dm_image img;
    if (dm_image_read(file, DM_PIXEL_U8, &img, &err) != DM_OK) {
        fail(r, "%s", err.detail);
        dm_image_free(&img);
        return;
    }
    const dm_param *table = img.has_provenance ? dm_prov_find(&img.prov, "table") : NULL;
    if (img.has_provenance && strcmp(img.prov.tool, "dermis-bake-lut") != 0 && !table) {
        /* a picture of dermis-render, dermis-view or dermis-reference: provenance only */
        r->type = "picture";
        check_prov(r, &img.prov, true, file);
        dm_image_free(&img);
        return;
    }
    check_prov(r, &img.prov, img.has_provenance, file);
    if (img.has_provenance) {
        const dm_param *t = table;
        if (!t || t->type != DM_PARAM_STRING || strcmp(t->s, "beckmann") != 0)
            fail(r, "%s: provenance table is \"%s\", expected \"beckmann\"", file, t ? t->s : "");
        if (prov_num(&img.prov, "width", img.width) != img.width || prov_num(&img.prov, "height", img.height) != img.height)
            fail(r, "%s: provenance size differs from the image's %dx%d", file, img.width, img.height);
    }
    if (img.channels != 1) {
        fail(r, "%s: %d channels, expected 1 (8-bit 0.5*D^0.1)", file, img.channels);
    } else {
        dm_lut_check c;
        dm_lut_check_beckmann(img.pixels, img.width, img.height, &c);
        report_lut(r, file, &c);
    }
    dm_image_free(&img);
}

static void check_directional_exr(result *r, const char *file, const dm_exr_image *img, bool env)
{
    check_prov(r, &img->prov, img->has_provenance, file);
    double f0 = prov_num(&img->prov, "f0", DM_SKIN_F0);
    int nodes = (int)prov_num(&img->prov, "nodes", 32);
    if (nodes < 8 || nodes > 128) {
        fail(r, "%s: provenance nodes %d, expected 8..128", file, nodes);
        nodes = 32;
    }
    const float *a = dm_exr_find(img, env ? "scale" : "rho_dt"), *b = env ? dm_exr_find(img, "bias") : NULL;
    if (!a || (env && !b)) {
        fail(r, "%s: missing channel %s", file, env ? "scale or bias" : "rho_dt");
        return;
    }
    size_t n = (size_t)img->width * img->height;
    float *inter = malloc(n * 2 * sizeof *inter);
    if (!inter) {
        fail(r, "%s: out of memory", file);
        return;
    }
    for (size_t i = 0; i < n; ++i) {
        inter[2 * i] = a[i];
        inter[2 * i + 1] = env ? b[i] : 0.0f;
    }
    dm_lut_check c;
    dm_lut_check_directional(inter, 2, env ? 2 : 1, img->width, img->height, f0, nodes, &c);
    report_lut(r, file, &c);
    free(inter);
}

static void check_exr(result *r, const char *file)
{
    dm_error err = {0};
    dm_exr_image img;
    if (dm_exr_read(file, &img, &err) != DM_OK) {
        fail(r, "%s", err.detail);
        dm_exr_free(&img);
        return;
    }
    if (dm_exr_find(&img, "stretch0.u") || dm_exr_find(&img, "mask")) {
        r->type = "stretch";
        check_stretch_exr(r, file, &img);
    } else if (dm_exr_find(&img, "rho_dt")) {
        r->type = "lut.rho_dt";
        check_directional_exr(r, file, &img, false);
    } else if (dm_exr_find(&img, "scale") && dm_exr_find(&img, "bias")) {
        r->type = "lut.env_brdf";
        check_directional_exr(r, file, &img, true);
    } else if (img.has_provenance) {
        r->type = !strcmp(img.prov.tool, "dermis-bake-env")   ? "env"
                  : !strcmp(img.prov.tool, "dermis-bake-lut") ? "lut.beckmann.float"
                                                              : "image";
        check_other(r, file, &img.prov, true, img.planes, img.channel_count, (size_t)img.width * img.height);
    } else {
        fail(r, "%s: no dermis provenance, and channels neither stretch<k>.u/.v + mask, rho_dt, nor scale + bias: "
                "not a dermis EXR",
             file);
    }
    dm_exr_free(&img);
}

/* --- packs -------------------------------------------------------------------------- */

static void check_pack(result *r, const char *file)
{
    dm_error err = {0};
    dm_pack pack;
    /* every entry's format and values (pack/dm_pack_semantic.h), as every reader of the pack
     * sees them; it stops at the first fault. What follows is dermis-check's own: entries the
     * scene does not need, provenance, LUT texels re-evaluated. */
    if (dm_pack_open(file, &pack, &err) != DM_OK) {
        fail(r, "%s", err.detail);
        return;
    }
    dm_scene *s = malloc(sizeof *s);
    if (!s || dm_pack_scene(&pack, s, &err) != DM_OK) {
        fail(r, "%s", s ? err.detail : "out of memory");
        free(s);
        dm_pack_close(&pack);
        return;
    }
    for (int k = 0; k < pack.entry_count; ++k) {
        const dm_pack_entry *e = &pack.entries[k];
        char where[1200];
        snprintf(where, sizeof where, "%s: entry \"%s\"", file, e->name);
        const dm_pack_need *nd = dm_pack_need_find(e->name);
        if (!nd)
            fail(r, "%s: not an entry dermis knows (dm_pack_needs.h)", where);
        else if (!dm_pack_entry_applies(e->name, s))
            fail(r, "%s: the scene's effects do not need it, expected it left out", where);
        dm_provenance p;
        bool has = e->provenance_json && dm_prov_from_json(&p, e->provenance_json, where, &err) == DM_OK;
        check_prov(r, &p, has, where);
        if (!strcmp(e->name, "lut.beckmann") && e->format == DM_TEX_R8) {
            dm_lut_check c;
            dm_lut_check_beckmann(e->data, e->width, e->height, &c);
            report_lut(r, where, &c);
        } else if ((!strcmp(e->name, "lut.rho_dt") && e->format == DM_TEX_R32F) ||
                   (!strcmp(e->name, "lut.env_brdf") && e->format == DM_TEX_RG32F)) {
            bool env = e->format == DM_TEX_RG32F;
            int nodes = has ? (int)prov_num(&p, "nodes", 32) : 32;
            dm_lut_check c;
            dm_lut_check_directional(e->data, env ? 2 : 1, env ? 2 : 1, e->width, e->height,
                                     has ? prov_num(&p, "f0", DM_SKIN_F0) : DM_SKIN_F0,
                                     nodes >= 8 && nodes <= 128 ? nodes : 32, &c);
            report_lut(r, where, &c);
        } else if (!strcmp(e->name, "stretch") && has) {
            /* cross-consistency of its provenance: built for this pack's mesh and mm_per_unit
             * (its values and layers were verified by dm_pack_open) */
            double mm = prov_num(&p, "mm_per_unit", NAN);
            if (mm != s->mm_per_unit)
                fail(r, "%s: built for mm_per_unit %g, the scene says %g", where, mm, s->mm_per_unit);
            const dm_pack_entry *mv = dm_pack_find(&pack, "mesh.vertices");
            dm_provenance mp;
            if (mv && mv->provenance_json && dm_prov_from_json(&mp, mv->provenance_json, where, &err) == DM_OK &&
                strcmp(mp.input_hash, p.input_hash) != 0)
                fail(r, "%s: built from mesh %s, the pack's mesh is %s", where, p.input_hash, mp.input_hash);
        }
    }
    note(r, "%d entries, %zu bytes, every checksum verified", pack.entry_count, pack.size);
    free(s);
    dm_pack_close(&pack);
}

/* --- main --------------------------------------------------------------------------- */

static void check_file(result *r, const char *file)
{
    dm_error ierr = {0}; /* core/dm_input.h: a regular file (a FIFO, a device, a folder said as such) */
    if (dm_input_check(file, DM_INPUT_ANY, NULL, &ierr) != DM_OK) {
        r->type = "unknown";
        fail(r, "%s", ierr.detail);
        return;
    }
    FILE *f = fopen(file, "rb");
    unsigned char magic[8] = {0};
    size_t got = f ? fread(magic, 1, 8, f) : 0;
    if (f) fclose(f);
    if (ends_with(file, ".dpk") || (got == 8 && memcmp(magic, DM_PACK_MAGIC, 8) == 0)) {
        r->type = "pack";
        check_pack(r, file);
    } else if (ends_with(file, ".png")) {
        r->type = "lut.beckmann";
        check_beckmann_png(r, file);
    } else if (ends_with(file, ".exr")) {
        r->type = "exr";
        check_exr(r, file);
    } else if (ends_with(file, ".json")) {
        char *text = NULL;
        size_t size = 0;
        dm_error err = {0};
        if (dm_input_read(file, DM_INPUT_JSON, &text, &size, &err) != DM_OK) {
            fail(r, "%s", err.detail);
            return;
        }
        /* Parsed once: the root tells a scene from a profile and is what either is read from. */
        const char *end = NULL;
        cJSON *root = cJSON_ParseWithOpts(text, &end, 0);
        if (end) end += strspn(end, " \t\r\n");
        bool whole = root && strlen(text) == size && end && !*end;
        const cJSON *fmt = cJSON_GetObjectItemCaseSensitive(root, "format");
        bool scene = cJSON_IsString(fmt) ? strcmp(fmt->valuestring, "dermis-scene") == 0
                                         : cJSON_GetObjectItemCaseSensitive(root, "mesh") != NULL;
        r->type = scene ? "scene" : "profile";
        if (scene)
            check_scene_json(r, file, root, text, size, whole);
        else
            check_profile_json(r, file, root);
        cJSON_Delete(root);
        free(text);
    } else {
        r->type = "unknown";
        fail(r, "%s: unknown file type, expected .dpk, .png, .exr or .json", file);
    }
}

int main(int argc, char **argv)
{
    bool json = false, verbose = false, quiet = false, fmt_version = false;
    int nfiles = 0, fmt_code = CHECK_OK;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (dm_cli_version(a, "dermis-check")) exit(0);
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return CHECK_OK;
        } else if (!strcmp(a, "--json")) {
            json = true;
        } else if (!strcmp(a, "--format-version")) {
            fmt_version = true;
        } else if (!strcmp(a, "--assets")) {
            const char *v = dm_cli_value(argc, argv, &i);
            if (!v) return CHECK_USAGE;
            if (g_asset_count == 8) {
                fprintf(stderr, "error: --assets: at most 8 folders\n");
                return CHECK_USAGE;
            }
            g_assets[g_asset_count++] = v;
        } else if (!strcmp(a, "-v") || !strcmp(a, "--verbose")) {
            verbose = true;
        } else if (!strcmp(a, "--quiet")) {
            quiet = true;
        } else if (!strcmp(a, "--")) {
            nfiles += argc - i - 1;
            break;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "error: unknown option '%s' (see --help)\n", a);
            return CHECK_USAGE;
        } else {
            ++nfiles;
        }
    }
    if (nfiles == 0) {
        fprintf(stderr, "error: no file given\n");
        usage(stderr);
        return CHECK_USAGE;
    }
    if ((verbose && quiet) || (fmt_version && (json || verbose))) {
        fprintf(stderr, "error: %s conflict\n", verbose && quiet ? "-v and --quiet" : "--format-version and -v/--json");
        return CHECK_USAGE;
    }
    result *r = malloc(sizeof *r);
    if (!r) return CHECK_FAILED;
    cJSON *out = json ? cJSON_CreateObject() : NULL;
    cJSON *files = out ? cJSON_AddArrayToObject(out, "files") : NULL;
    int failed = 0;
    bool files_only = false;
    for (int i = 1; i < argc; ++i) {
        if (!files_only && !strcmp(argv[i], "--")) {
            files_only = true;
            continue;
        }
        if (!files_only && !strcmp(argv[i], "--assets")) {
            ++i;
            continue;
        }
        if (!files_only && argv[i][0] == '-' && argv[i][1]) continue;
        if (fmt_version) { /* pack/dm_format_version.h: reads only what names the version */
            dm_format_version v;
            dm_error e = {0};
            int c = dm_format_version_read(argv[i], &v, &e) != DM_OK ? CHECK_USAGE : v.verdict != DM_FORMAT_READABLE;
            if (c == CHECK_USAGE) fprintf(stderr, "error: %s\n", e.detail);
            else if (c || !quiet) printf("%s: %s\n", argv[i], v.summary);
            fmt_code = c > fmt_code ? c : fmt_code;
            continue;
        }
        memset(r, 0, sizeof *r);
        r->file = argv[i];
        check_file(r, argv[i]);
        failed += r->count > 0;
        if (json) {
            cJSON *o = cJSON_CreateObject();
            cJSON_AddStringToObject(o, "file", r->file);
            cJSON_AddStringToObject(o, "type", r->type ? r->type : "unknown");
            if (r->made_by[0]) cJSON_AddStringToObject(o, "made_by", r->made_by);
            cJSON_AddBoolToObject(o, "ok", r->count == 0);
            cJSON *fl = cJSON_AddArrayToObject(o, "failures");
            for (int k = 0; k < r->count; ++k) cJSON_AddItemToArray(fl, cJSON_CreateString(r->failures[k]));
            cJSON *nt = cJSON_AddArrayToObject(o, "notes");
            for (int k = 0; k < r->notes; ++k) cJSON_AddItemToArray(nt, cJSON_CreateString(r->note[k]));
            cJSON_AddItemToArray(files, o);
        } else if (r->count == 0) {
            if (!quiet) {
                if (r->made_by[0])
                    printf("%s: ok (%s, made by %s)\n", r->file, r->type ? r->type : "unknown", r->made_by);
                else
                    printf("%s: ok (%s)\n", r->file, r->type ? r->type : "unknown");
            }
            if (verbose)
                for (int k = 0; k < r->notes; ++k) printf("  %s\n", r->note[k]);
        } else {
            for (int k = 0; k < r->count; ++k) printf("%s: FAIL: %s\n", r->file, r->failures[k]);
            if (r->count == MAX_FAILURES) printf("%s: FAIL: (more failures not shown)\n", r->file);
        }
    }
    if (json) {
        cJSON_AddBoolToObject(out, "ok", failed == 0);
        char *t = cJSON_Print(out);
        printf("%s\n", t);
        cJSON_free(t);
        cJSON_Delete(out);
    }
    free(r);
    return failed ? CHECK_FAILED : fmt_code;
}
