/* accuracy_refs.h — the accuracy bench's references (bench/accuracy.c): the texture-space
 * truths and the frame's, computed by dermis-reference when missing and cached under the build's
 * cache by pack hash, truth and settings, reused while their provenance matches. Included once,
 * by bench/accuracy.c, after common/accuracy_packs.h. */
#ifndef BENCH_ACCURACY_REFS_H
#define BENCH_ACCURACY_REFS_H

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/dm_prov.h"
#include "render/dm_render.h"
#include "render/dm_render_refcmp.h"
#include "common/accuracy_rows.h"
#include "common/accuracy_packs.h"

/* The option naming a truth: burley, skin or dipole (NULL: the pack's own profile). */
static const char *truth_kind(const char *spec)
{
    return !spec ? NULL : spec == BURLEY ? "burley" : spec == SKIN ? "skin" : "dipole";
}

/* The reference of truth dip (NULL: the pack's profile) at texture-space size N, or (N 0) the
 * frame without `without`; step (frames only) -1 for the bench's settings, else a margin's step
 * (frame_truth.h, FT_*): the rays a step back (the scene profile's without --refine, the
 * dipole's at 2²), the atlas at half (its samples doubled: the same irradiance points), or the
 * quadrature's pair (atlas 1024 × 4², one ray, the default quadrature, then cut 6 σ and spacing
 * 0.15 σ). Cached under dir by pack hash and settings. */
static int reference(const char *bin, const char *pack, const char *hash, const char *dir, int N, const char *dip,
                     const char *without, int step, dm_refcmp_ref *ref)
{
    const char *hex = strchr(hash, ':') ? strchr(hash, ':') + 1 : hash, *kind = truth_kind(dip);
    char path[2048], cmd[8192], truth[64] = "", opt[200] = "", wo[64] = "";
    char spec[DM_PROV_STRING_SIZE] = "";
    if (dip == SKIN && !skin_spec(spec, sizeof spec)) return 0;
    if (dip == SKIN) /* the preset by name, its representation's size in the file name */
        snprintf(truth, sizeof truth, "skin-%s-g%d-", SKIN, SKIN_RADIAL),
            snprintf(opt, sizeof opt, " --skin-preset %s --radial-gaussians %d", SKIN, SKIN_RADIAL);
    else if (dip) {
        snprintf(truth, sizeof truth, "%s-%s-", kind, dip), snprintf(opt, sizeof opt, " --%s %s", kind, dip);
        for (char *t = truth; *t; ++t) /* the spec's '/', ',' and '.' out of the file name */
            if (!((*t >= 'a' && *t <= 'z') || (*t >= '0' && *t <= '9') || *t == '-')) *t = '_';
    }
    if (without) { /* the frame's runs: "-without-albedo_normal-map_shadows" */
        snprintf(wo, sizeof wo, "-without-%s", without);
        for (char *t = wo; *t; ++t) *t = *t == ',' ? '_' : *t;
        snprintf(opt + strlen(opt), sizeof opt - strlen(opt), " --without %s", without);
    }
    /* the scene profile's transport runs (white albedo: the transport and its flat) refined and
     * at the finer atlas, where the rankings are read; not the dipole's (twelve times the time) */
    bool quad = step == FT_QUAD_BASE || step == FT_QUAD_FINE, fine = step == FT_QUAD_FINE;
    bool transport = !dip && without && strstr(without, "albedo");
    int refine = transport && step != FT_COARSE_RAYS && !quad ? FRAME_REFINE : 0;
    int atlas = transport ? TRANSPORT_ATLAS : FRAME_ATLAS, as = transport ? TRANSPORT_AS : FRAME_AS;
    if (step == FT_COARSE_ATLAS) atlas /= 2, as *= 2;
    if (quad) atlas = QUAD_ATLAS, as = QUAD_AS;
    int ps = quad ? 1 : dip && step == FT_COARSE_RAYS ? FRAME_PS - 1 : FRAME_PS;
    double cut = fine ? QUAD_CUT : 4, spacing = fine ? QUAD_SPACING : 0.3;
    char q[40] = "";
    if (fine) snprintf(q, sizeof q, "-q%g-%g", cut, spacing);
    if (N) snprintf(path, sizeof path, "%s/ref-%.16s-%s%d.exr", dir, hex, truth, N);
    else snprintf(path, sizeof path, "%s/frame-%.16s-%s%dx%d-%d-%d-%d-r%d%s%s.exr", dir, hex, truth, FW, FH, atlas, as,
                  ps, refine, q, wo);
    dm_error err = {0};
    for (int attempt = 0; attempt < 2; ++attempt) {
        if (dm_refcmp_load(path, ref, &err) == DM_OK && ref->has_provenance &&
            !strcmp(ref->prov.tool, "dermis-reference") && !strcmp(ref->prov.input_hash, hash) &&
            ref->mode == (N ? DM_REFCMP_TEXTURE_SPACE : DM_REFCMP_FRAME) &&
            (N ? ref->width == N : ref->width == FW && ref->height == FH)) {
            const dm_param *tc = dm_prov_find(&ref->prov, "tile_count"), *dp = dm_prov_find(&ref->prov, "dipole");
            const dm_param *bp = dm_prov_find(&ref->prov, "burley"), *mine = dip == BURLEY ? bp : dp;
            const dm_param *sk = dm_prov_find(&ref->prov, "skin"), *rg = dm_prov_find(&ref->prov, "radial_gaussians");
            const dm_param *pp = dm_prov_find(&ref->prov, "pixel_samples"); /* frames: anti-aliased */
            const dm_param *df = dm_prov_find(&ref->prov, "diffusion"), *wt = dm_prov_find(&ref->prov, "without");
            bool truth_ok = dip == SKIN ? sk && !strcmp(sk->s, spec) && rg && rg->i == SKIN_RADIAL && !dp && !bp
                            : dip ? mine && !strcmp(mine->s, dip) && !(dip == BURLEY ? dp : bp) && !sk
                                  : !dp && !bp && !sk;
            const dm_param *rf = dm_prov_find(&ref->prov, "refine_samples");
            const dm_param *at = dm_prov_find(&ref->prov, "atlas"), *sa = dm_prov_find(&ref->prov, "atlas_samples");
            const dm_param *qc = dm_prov_find(&ref->prov, "cut_sigma"), *qs = dm_prov_find(&ref->prov, "spacing_sigma");
            bool frame_ok = pp && pp->i == ps && (refine ? rf && rf->i == refine : !rf) && df && !strcmp(df->s, "pixel") &&
                            wt && !strcmp(wt->s, without ? without : "") && at && at->i == atlas && sa && sa->i == as &&
                            qc && fabs(qc->d - cut) < 1e-9 && qs && fabs(qs->d - spacing) < 1e-9;
            /* texture space: the renderer's irradiance at this build's shadow map size */
            char shadow[48];
            snprintf(shadow, sizeof shadow, ", shadow map %d (", DM_RENDER_SHADOW_SIZE_DEFAULT);
            const dm_param *ir = dm_prov_find(&ref->prov, "irradiance");
            bool irr_ok = !N || (ir && strstr(ir->s, shadow));
            if ((!tc || tc->i == 1) && truth_ok && (N || frame_ok) && irr_ok) {
                fprintf(stderr, "accuracy bench: reference %s (%s)\n", path, attempt ? "computed" : "cached");
                return 1;
            }
        }
        dm_refcmp_ref_free(ref);
        if (attempt) break;
        if (N) snprintf(cmd, sizeof cmd, "%s/bin/dermis-reference %s --texture-space %d%s -o %s --quiet", bin, pack, N, opt, path);
        else {
            char rk[64] = "";
            if (refine) snprintf(rk, sizeof rk, " --refine %d", refine);
            if (fine) snprintf(rk + strlen(rk), sizeof rk - strlen(rk), " --cut %g --spacing %g", cut, spacing);
            snprintf(cmd, sizeof cmd,
                     "%s/bin/dermis-reference %s --frame --size %dx%d --atlas %d --atlas-samples %d --pixel-samples %d%s%s -o %s "
                     "--quiet",
                     bin, pack, FW, FH, atlas, as, ps, rk, opt, path);
        }
        if (run(cmd) != 0) break;
    }
    fprintf(stderr, "error: no usable reference %s: %s\n", path, err.detail);
    return 0;
}

#endif
