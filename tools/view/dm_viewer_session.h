/* dm_viewer_session.h — dermis-view's session state (dm_viewer: the assets, the renderer,
 * the edited scene, the knobs, the display) and the two things every feature may ask of it:
 * a status message and a rebuild of the renderer for the edited scene. The features
 * (dm_viewer_camera.c, dm_viewer_compare.c, dm_viewer_technique.c) stand on this file
 * only; dm_viewer.c sits on top of them all and calls them.
 */
#ifndef DM_VIEWER_SESSION_H
#define DM_VIEWER_SESSION_H

#include <stdbool.h>
#include <stdint.h>

#include "bake/dm_skin_weights.h"
#include "pack/dm_pack.h"
#include "core/dm_scene.h"
#include "render/dm_render.h"
#include "render/dm_render_refcmp.h"
#include "render/dm_render_synth.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_VIEWER_MAX_VIEWS = 32, DM_VIEWER_STATUS_SIZE = 1024 };

/* --reference: the comparison with a ground truth (dm_viewer_compare.c). While `on`, every
 * frame renders the view the reference matches (diffusion or final) and the picture is
 * dm_refcmp_compose's: side by side, split at `split`, or the error map, with the legend. */
typedef struct dm_viewer_compare {
    bool loaded, on;
    char path[1024];
    dm_refcmp_ref ref;
    dm_refcmp_layout layout;
    float split;       /* divider, [0, 1] of the picture width */
    float error_scale; /* relative error at the top of the colour scale */
    dm_refcmp_stats stats;
    bool has_stats;
    char text[1024]; /* dm_refcmp_stats_text of the last frame */
} dm_viewer_compare;

enum { DM_VIEWER_SKIN_TIMES = 256 };

/* The live physical skin (dm_viewer_skin.c): the sliders' parameters, the plan of the
 * loaded profile's variances, and the scale the renderer applies (also after a rebuild). */
typedef struct dm_viewer_skin {
    bool available, from_pack, changed;
    char off_reason[256];    /* why not available */
    dm_skin_params start, now;
    double start_total[3];   /* the starting skin's colorimetric totals (dm_skin_weights_fit_colour) */
    double scale_rgb[3];     /* now's total over start's, per channel */
    dm_skin_weights_plan plan;
    double ms[DM_VIEWER_SKIN_TIMES]; /* refit + hand-over per change, ring */
    int ms_count;
} dm_viewer_skin;

typedef struct dm_viewer_options {
    const char *pack;       /* PACK path, or NULL with synthetic */
    const char *synthetic;  /* "sphere" or "quad", or NULL */
    const char *shader_dir; /* NULL: embedded shaders */
    int width, height;      /* render and window size, px */
    int irradiance_size;    /* texture-space size, 0 = 512 (llvmpipe stays responsive) */
    dm_view view;
    int view_index;
    float view_scale; /* debug texture views, 0 = 1 */
    float light_azimuth_deg;
    bool watch, verbose, quiet;
} dm_viewer_options;

typedef struct dm_viewer {
    dm_viewer_options opt;
    /* assets */
    dm_pack pack;
    bool pack_open;
    dm_synth *synth;
    dm_scene loaded;  /* the scene as loaded (reset target) */
    dm_scene scene;   /* the edited copy the renderer shows */
    dm_profile profile;
    dm_render_assets assets; /* assets.scene = &scene */
    dm_renderer *r;
    /* camera: orbit around target; applied to scene.camera_* once moved, so an untouched
     * camera is exactly the scene's (dermis-render gives the same picture) */
    float yaw_deg, pitch_deg, distance, target[3];
    bool camera_moved;
    /* per-frame knobs */
    dm_view view;
    int view_index;
    float view_scale, blur_scale, roughness_scale, light_rotation_deg;
    bool light_rotating;
    float rotate_deg_per_s;
    int light; /* the light the panel and light drag edit */
    int irradiance_size;
    /* packed environments (dm_render_env_count): env is the one shown, 0 = the main map */
    int env, env_count;
    /* debug views available in the current pass list */
    int view_count;
    char view_names[DM_VIEWER_MAX_VIEWS][16];
    /* display */
    bool dirty, show_help, show_panel, quit;
    uint8_t *rgba; /* width*height*4, the last frame, bottom-up */
    unsigned tex;  /* GL texture showing it */
    int frames;
    double pass_ms[DM_PLAN_MAX_PASSES], frame_ms, ui_ms;
    int gl_errors;     /* GL errors seen outside the renderer (UI, display) */
    int failures;      /* actions that failed (scripts exit non-zero) */
    char status[DM_VIEWER_STATUS_SIZE]; /* the last message, shown in the panel */
    int shot_count;
    dm_viewer_compare cmp;
    dm_viewer_skin skin;
    /* technique split (dm_viewer_technique.c): the other subsurface technique rendered by a
     * second renderer beside this one, through the comparison's split/side/error machinery */
    bool tsplit;
    dm_renderer *r_other;
    dm_scene scene_other;
    /* --watch */
    long long watch_mtime_ns, watch_size;
    double watch_next_ms;
} dm_viewer;

/* Sets v->status; an error also goes to stderr and counts in v->failures, a message to
 * stderr with --verbose. */
void dm_viewer_set_status(dm_viewer *v, bool error, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
/* Creates the renderer over v->assets for v->scene (the previous one destroyed) and lists
 * the debug views its pass list offers; needs the current GL context. */
dm_result dm_viewer_create_renderer(dm_viewer *v, dm_error *err);
/* Recreates the renderer for the edited scene, restoring `previous` on failure (what: the
 * status text). */
bool dm_viewer_rebuild(dm_viewer *v, const dm_scene *previous, int previous_irr, const char *what);

#ifdef __cplusplus
}
#endif
#endif
