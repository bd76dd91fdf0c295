/* accuracy_packs.h — the accuracy bench's packs (bench/accuracy.c): the scene's variants that
 * its rows render — N Gaussians fitted to a profile, Burley, the physical skin, the
 * pre-integrated technique — made by dermis-pack from SCENE with one key replaced, cached
 * under the build's cache by the base pack's hash while this build's renderer still reads
 * them; and the shell commands it runs, echoed. Included once, by bench/accuracy.c, after
 * common/accuracy_report.h. */
#ifndef BENCH_ACCURACY_PACKS_H
#define BENCH_ACCURACY_PACKS_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bake/dm_skin_optics.h"
#include "bake/dm_skin_spec.h"
#include "pack/dm_pack.h"
#include "render/dm_render_pack.h"

static int run(const char *cmd)
{
    fprintf(stderr, "accuracy bench: %s\n", cmd);
    return system(cmd);
}

/* SKIN's parameters as dermis-reference and dermis-pack write them into the provenance
 * ("skin": dm_skin_spec_format, 17 digits), so a reference or pack of a preset since
 * changed is made again. */
static int skin_spec(char *buf, int size)
{
    dm_skin_params p;
    dm_error err = {0};
    if (dm_skin_preset(SKIN, &p, &err) != DM_OK) {
        fprintf(stderr, "error: skin preset %s: %s\n", SKIN, err.detail);
        return 0;
    }
    dm_skin_spec_format(&p, 17, buf, size);
    return 1;
}

/* The pack of SCENE with `key` replaced by `value` (the scene written beside the original,
 * so its relative paths hold, and removed again) at pack_path; tag names the scene file. */
static int pack_variant(const char *bin, const char *key, const char *value, const char *tag, const char *pack_path)
{
    char scene[1024], cmd[8192];
    FILE *f = fopen(SCENE, "rb");
    char text[16384];
    size_t len = f ? fread(text, 1, sizeof text - 1, f) : 0;
    if (f) fclose(f);
    text[len] = 0;
    char *at = strstr(text, key);
    if (!at) {
        fprintf(stderr, "error: %s: no %s to replace\n", SCENE, key);
        return 0;
    }
    snprintf(scene, sizeof scene, "assets/scenes/.accuracy-%s-%ld.json", tag, (long)getpid());
    f = fopen(scene, "wb");
    if (!f) return 0;
    fprintf(f, "%.*s%s%s", (int)(at - text), text, value, at + strlen(key));
    fclose(f);
    snprintf(cmd, sizeof cmd, "%s/bin/dermis-pack %s -o %s --quiet", bin, scene, pack_path);
    int rc = run(cmd);
    remove(scene);
    return rc == 0;
}

/* A cached variant pack that this build's renderer still reads (the pack format may have
 * grown since it was written: then it is packed again). */
static int cached(const char *path)
{
    if (access(path, R_OK) != 0) return 0;
    dm_pack pack;
    dm_scene scene;
    dm_profile profile;
    dm_render_assets assets;
    int ok = dm_pack_open(path, &pack, NULL) == DM_OK;
    if (ok) {
        ok = dm_render_assets_from_pack(&pack, &scene, &profile, &assets, NULL) == DM_OK;
        dm_pack_close(&pack);
    }
    if (!ok) fprintf(stderr, "accuracy bench: %s is stale, packing it again\n", path);
    return ok;
}

/* The pack of g Gaussians fitted to gems3-skin (or the dipole): the scene's profile pointing
 * at the fit. Cached by the base pack's hash (the scene) and the source (fits are
 * deterministic). */
static int pack_fit(const char *bin, const char *dir, const char *hash, int g, char *pack_path, size_t size)
{
    const char *hex = strchr(hash, ':') ? strchr(hash, ':') + 1 : hash;
    char fit[4096], cmd[8192], absdir[3072], cwd[2048], value[4200], tag[16];
    if (dir[0] == '/') snprintf(absdir, sizeof absdir, "%s", dir);
    else if (getcwd(cwd, sizeof cwd)) snprintf(absdir, sizeof absdir, "%s/%s", cwd, dir);
    else return 0;
    snprintf(fit, sizeof fit, "%s/fit-%s-%d.json", absdir, dipole ? dipole : "gems3", g);
    snprintf(pack_path, size, "%s/lps-sss-%.16s-%s-g%d.dpk", dir, hex, dipole ? dipole : "gems3", g);
    if (!access(fit, R_OK) && cached(pack_path)) return 1;
    snprintf(cmd, sizeof cmd, "%s/bin/dermis-fit-profile %s%s -n %d -o %s --quiet", bin, dipole ? "--dipole " : "--preset ",
             dipole ? dipole : "gems3-skin", g, fit);
    if (run(cmd) != 0) return 0;
    snprintf(value, sizeof value, "\"profile\": \"%s\"", fit);
    snprintf(tag, sizeof tag, "g%d", g);
    return pack_variant(bin, "\"profile\": \"gems3-skin\"", value, tag, pack_path);
}

/* The pack whose profile is BURLEY fitted by BURLEY_G Gaussians (cached like pack_fit). */
static int pack_burley(const char *bin, const char *dir, const char *hash, char *pack_path, size_t size)
{
    const char *hex = strchr(hash, ':') ? strchr(hash, ':') + 1 : hash;
    char fit[4096], cmd[8192], absdir[3072], cwd[2048], value[4200];
    if (dir[0] == '/') snprintf(absdir, sizeof absdir, "%s", dir);
    else if (getcwd(cwd, sizeof cwd)) snprintf(absdir, sizeof absdir, "%s/%s", cwd, dir);
    else return 0;
    snprintf(fit, sizeof fit, "%s/fit-burley-%d.json", absdir, BURLEY_G);
    snprintf(pack_path, size, "%s/lps-sss-%.16s-burley-g%d.dpk", dir, hex, BURLEY_G);
    if (!access(fit, R_OK) && cached(pack_path)) return 1;
    snprintf(cmd, sizeof cmd, "%s/bin/dermis-fit-profile --burley --albedo 0.8,0.6,0.4 --mfp 1,0.5,0.25 -n %d -o %s --quiet",
             bin, BURLEY_G, fit);
    if (run(cmd) != 0) return 0;
    snprintf(value, sizeof value, "\"profile\": \"%s\"", fit);
    return pack_variant(bin, "\"profile\": \"gems3-skin\"", value, "burley", pack_path);
}

/* The pack whose profile is the physical skin SKIN, fitted by dermis-pack itself (SKIN_G
 * Gaussians, normalised to white). Cached by the base pack's hash while its "profile" entry's
 * provenance holds SKIN's parameters as they are now. */
static int pack_skin(const char *bin, const char *dir, const char *hash, char *pack_path, size_t size)
{
    const char *hex = strchr(hash, ':') ? strchr(hash, ':') + 1 : hash;
    char spec[DM_PROV_STRING_SIZE], value[200];
    if (!skin_spec(spec, sizeof spec)) return 0;
    snprintf(pack_path, size, "%s/lps-sss-%.16s-skin-%s-g%d.dpk", dir, hex, SKIN, SKIN_G);
    if (cached(pack_path)) {
        dm_pack pack;
        dm_provenance prov;
        const dm_pack_entry *e;
        const dm_param *sk = NULL;
        if (dm_pack_open(pack_path, &pack, NULL) == DM_OK) {
            if ((e = dm_pack_find(&pack, "profile")) && e->provenance_json &&
                dm_prov_from_json(&prov, e->provenance_json, pack_path, NULL) == DM_OK)
                sk = dm_prov_find(&prov, "skin");
            bool same = sk && !strcmp(sk->s, spec);
            dm_pack_close(&pack);
            if (same) return 1;
        }
        fprintf(stderr, "accuracy bench: %s is not of the skin %s now, packing it again\n", pack_path, spec);
    }
    snprintf(value, sizeof value, "\"profile\": {\"skin\": {\"preset\": \"%s\"}}", SKIN);
    return pack_variant(bin, "\"profile\": \"gems3-skin\"", value, "skin", pack_path);
}

/* The scene with `key` replaced by `value`, packed once per base pack (lps-sss-HASH-TAG.dpk)
 * while this build's renderer still reads it. */
static int pack_keyed(const char *bin, const char *dir, const char *hash, const char *key, const char *value,
                      const char *tag, char *pack_path, size_t size)
{
    const char *hex = strchr(hash, ':') ? strchr(hash, ':') + 1 : hash;
    snprintf(pack_path, size, "%s/lps-sss-%.16s-%s.dpk", dir, hex, tag);
    return cached(pack_path) || pack_variant(bin, key, value, tag, pack_path);
}

/* The scene as the pre-integrated technique packs it (its table and curvature map). */
static int pack_preint(const char *bin, const char *dir, const char *hash, char *pack_path, size_t size)
{
    return pack_keyed(bin, dir, hash, "\"taps\": 7, \"irradiance_size\": 1024,", "\"technique\": \"pre-integrated\",",
                      "preint", pack_path, size);
}

/* The scene packed at irradiance 2048: its seam and thin-part maps and its thin gather baked
 * for that size (the renderer uploads them at the size they were baked for and leaves them out
 * at any other: the 2048 row rendered from the 1024 pack has none of them). On the head at 2048²
 * the gather's texels share their taps in blocks of 2 × 2 (one run each would pass what a pack
 * carries). */
static int pack_2048(const char *bin, const char *dir, const char *hash, char *pack_path, size_t size)
{
    return pack_keyed(bin, dir, hash, "\"irradiance_size\": 1024", "\"irradiance_size\": 2048", "i2048", pack_path, size);
}

/* The scene with translucency asked for (intensity 1): the "+ transl." rows render it (the
 * scene's own pack, which does not ask for it, gives the renderer no intensity to transmit
 * with, and the rows equalled their base rows). In texture space it still adds nothing by
 * design: the thin-part map carries that light (--explain says so). */
static int pack_transl(const char *bin, const char *dir, const char *hash, char *pack_path, size_t size)
{
    return pack_keyed(bin, dir, hash, "\"shadows\": true,", "\"translucency\": { \"intensity\": 1.0 }, \"shadows\": true,",
                      "transl", pack_path, size);
}

#endif
