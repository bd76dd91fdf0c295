/* bench/common/accuracy_rows.h — bench/accuracy's settings and rows: the frame references'
 * settings, the truths, the packs, a row's results and the rows by name. Header-only like
 * bench_util.h; included by frame_rankings.h and accuracy_report.h. */
#ifndef BENCH_ACCURACY_ROWS_H
#define BENCH_ACCURACY_ROWS_H

#include <stdbool.h>
#include <string.h>

#include "reference/dm_ref_regions.h"
#include "pack/dm_pack.h"
#include "render/dm_render.h"
#include "render/dm_render_refcmp.h"

#include "common/frame_truth.h"

/* The frame references: at the frame size, atlas FRAME_ATLAS with FRAME_AS² samples a texel,
 * FRAME_PS² sub-pixel rays a pixel with the diffusion at each (the converged defaults of
 * dermis-reference --frame: docs/dermis-reference.md, Convergence), and in the scene profile's
 * transport runs (transport and its flat, where the rankings are read) the pixels whose rays
 * spread shaded again from FRAME_REFINE² rays (--refine; issue #27) and the atlas a step finer,
 * TRANSPORT_ATLAS with TRANSPORT_AS² samples (the same irradiance points; 39 min on 2 cores):
 * at 4096 the atlas was the largest term of the TSD 1024 -> 2048 margin's bar. The surface and
 * full runs stay at FRAME_PS² and FRAME_ATLAS: there the albedo and normal map's texture spreads
 * nearly every pixel's rays, so --refine would shade nearly all again (over 3x the time), and
 * the rays move their mean error by about 0.1 % (3² -> 4² with D at the centre 0.03 %; the
 * transport's 2² -> 3² step, 12 % of a subsurface signal of about 1 % of the value), the atlas
 * 2048 -> 4096 by 0.1-0.25 %, a tenth of what they report; the dipole's transport (hours at
 * 3²) stays at FRAME_ATLAS too. */
enum { W = 1280, H = 720, FW = 1280, FH = 720, FRAME_ATLAS = 4096, FRAME_AS = 2, FRAME_PS = 3, FRAME_REFINE = 8 };
enum { TRANSPORT_ATLAS = 8192, TRANSPORT_AS = 1 };
/* The quadrature's step for a margin's bar (frame_truth.h, FT_QUAD_*): at atlas QUAD_ATLAS with
 * QUAD_AS² samples and one ray at the pixel centre (the convergence table's setting for it), the
 * default quadrature (cut 4 sigma, spacing 0.3 sigma) against cut QUAD_CUT, spacing QUAD_SPACING. */
enum { QUAD_ATLAS = 1024, QUAD_AS = 4 };
#define QUAD_CUT 6.0
#define QUAD_SPACING 0.15
enum { MAX_FRAMES = 64, MAX_ROWS = 48, MAX_G = 8 };
/* packs[]: 0 the scene's, g fitted to g Gaussians, pre-integrated, Burley's fit, the physical skin's fit, the scene at irradiance 2048, with translucency */
enum { PACK_PREINT = MAX_G + 1, PACK_BURLEY, PACK_SKIN, PACK_2048, PACK_TRANSL, NPACKS };
enum { MAX_SIZED = 8 }; /* texture-space references: one per (size, truth) */
enum { REG_ALL = DM_REF_REGION_COUNT, NREG = DM_REF_REGION_COUNT + 1 }; /* stats index: region, or all */
static const char *SCENE = "assets/scenes/lps-sss.json";

typedef struct setting {
    char name[40], what[160];
    int size, taps, gaussians; /* irradiance size; blur taps (0: the scene's); 0: the pack's profile */
    bool flat_stretch;
    bool no_seam;       /* the pack's seam map left out: blurs stop at UV seams (before #29) */
    bool no_thin;       /* the pack's thin-part map left out: no light across thin parts (before #29) */
    bool no_gather;     /* the pack's thin gather left out: the widest levels from the atlas blur */
    dm_sss_technique technique; /* texture-space (0), screen-space or pre-integrated (its own pack:
                                 * the table and curvature map, PACK_PREINT) */
    int screen_taps;            /* screen-space kernel taps */
    bool translucency;
    bool burley; /* its own truth and pack: a Gaussian fit of BURLEY against BURLEY itself */
    bool skin;   /* its own truth and pack: the packer's fit of the physical skin SKIN against SKIN itself */
    bool frame_only;    /* no texture-space comparison (2048: its reference takes 15+ min) */
    bool no_subsurface; /* the floor: the renderer's Lambert, subsurface off */
    bool technique_row; /* a technique at the scene's settings or finer: must beat the floor */
    dm_render_desc knobs;
} setting;

/* A Gaussian-count row: N Gaussians fitted to the truth (the dipole, or gems3-skin). */
static bool fit_row(const setting *s)
{
    return s->gaussians && !s->burley && !s->skin;
}

/* The truth the Gaussian-count rows are fitted to and compared with: the skin1 dipole when
 * dermis-reference can convolve it (--dipole), else gems3-skin itself. */
static const char *dipole;

/* The Burley profile of the Burley row (docs/pre-integrated.md's example): albedo / mean
 * free path (mm) per channel, as dermis-reference --burley takes it; fitted by BURLEY_G
 * Gaussians. */
static const char *const BURLEY = "0.8,0.6,0.4/1,0.5,0.25";
enum { BURLEY_G = 6 };

/* The physical skin of the skin rows (docs/skin-model.md): a dermis-fit-profile preset. The
 * pack's profile is {"skin": {"preset": SKIN}}, which dermis-pack fits by SKIN_G Gaussians
 * normalised to white; the truth is dermis-reference --skin-preset SKIN, the model's own R(r)
 * represented by SKIN_RADIAL Gaussians, each channel's weights normalised to sum 1 as well. */
static const char *const SKIN = "caucasian";
enum { SKIN_G = 6, SKIN_RADIAL = 32 };

typedef struct sized {
    int N;
    const char *dipole; /* the truth's spec: NULL the pack's profile, dipole, BURLEY or SKIN */
    dm_refcmp_ref ref;
    uint8_t *label;
    float *area;
    long count[DM_REF_REGION_COUNT];
    double area_mm2[DM_REF_REGION_COUNT];
} sized;

typedef struct packed {
    bool open;
    dm_pack pack;
    dm_scene scene;
    dm_profile profile;
    dm_render_assets assets;
} packed;

typedef struct row {
    setting s;
    dm_scene scene;
    dm_renderer *r;
    double ms[MAX_FRAMES], frame_ms;
    dm_ref_error_stats st[NREG];
    bool ok[NREG], fok;        /* fok: the transport run compared */
    frame_result fr;
    const frame_truth *ft;     /* the frame references of its truth */
} row;

static setting rows_s[MAX_ROWS];
static int nrows;

/* A row by its short name, or NULL. */
static const row *row_named(const row *rows, const char *name)
{
    for (int c = 0; c < nrows; ++c)
        if (!strcmp(rows[c].s.name, name) && rows[c].fok) return &rows[c];
    return NULL;
}

#endif
