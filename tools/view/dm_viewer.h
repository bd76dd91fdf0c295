/* dm_viewer.h — the state and actions of dermis-view, shared by the window callbacks,
 * the UI panel (dm_viewer_ui.h, C++) and the script player (dm_viewer_script.h): every
 * input path calls the same actions, so a script exercises what a person does.
 *
 * The viewer owns one renderer (lib/render) over assets that come either from an open
 * pack (pointers into its mapping) or from the synthetic scene. It keeps an edited copy
 * of the scene: values no pass depends on (camera, lights, exposure, mix, environment
 * intensity and rotation) reach the renderer through dm_renderer_set_scene; changes of
 * the pass list (effects, environment background, irradiance size) recreate the renderer
 * from the same assets. It renders on demand: only when something changed (`dirty`).
 */
#ifndef DM_VIEWER_H
#define DM_VIEWER_H

#include <stdbool.h>
#include <stdint.h>

#include "pack/dm_pack.h"
#include "core/dm_prov.h"
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
    /* technique split (dm_viewer_technique.c): the other subsurface technique rendered by a
     * second renderer beside this one, through the comparison's split/side/error machinery */
    bool tsplit;
    dm_renderer *r_other;
    dm_scene scene_other;
    /* --watch */
    long long watch_mtime_ns, watch_size;
    double watch_next_ms;
} dm_viewer;

/* Loads the pack (dm_pack_open verifies all of it) or builds the synthetic scene.
 * Returns DM_ERR_FILE_OPEN when the pack is missing, the validator's error when it is
 * corrupt (err->detail is dermis-check's message). No GL needed. */
dm_result dm_viewer_load(dm_viewer *v, const dm_viewer_options *opt, dm_error *err);
/* Creates the renderer and the display texture; needs the current GL context. */
dm_result dm_viewer_start(dm_viewer *v, dm_error *err);
void dm_viewer_free(dm_viewer *v);

/* Renders a frame if dirty and uploads it to v->tex. Failures go to v->status and
 * stderr and count in v->failures; the viewer then falls back to the final view. */
void dm_viewer_update(dm_viewer *v, double dt_s);

/* actions (each marks the frame dirty and returns false, with v->status set, on failure) */
/* dm_viewer_camera.c: the orbit from the loaded scene's camera; into the scene's camera. */
void dm_viewer_camera_from_scene(dm_viewer *v);
void dm_viewer_apply_camera(dm_viewer *v);
void dm_viewer_orbit(dm_viewer *v, float dx_px, float dy_px);
void dm_viewer_pan(dm_viewer *v, float dx_px, float dy_px);
void dm_viewer_zoom(dm_viewer *v, float wheel_steps);
void dm_viewer_drag_light(dm_viewer *v, float dx_px, float dy_px);
void dm_viewer_reset_camera(dm_viewer *v);
bool dm_viewer_set_effect(dm_viewer *v, dm_effect e, bool on);
bool dm_viewer_set_background(dm_viewer *v, bool on);
bool dm_viewer_set_irradiance(dm_viewer *v, int size);
/* Shows packed environment k in [0, env_count) (0 = the scene's main map, k = its k-th
 * alternative): the renderer is recreated over that environment's entries (no copies). */
bool dm_viewer_set_env(dm_viewer *v, int k);
/* The file name of packed environment k (from its provenance, else the scene). */
void dm_viewer_env_name(const dm_viewer *v, int k, char *out, int size);
bool dm_viewer_set_view(dm_viewer *v, const char *name);
bool dm_viewer_cycle_view(dm_viewer *v, int step);
/* "exposure", "mix", "blur_scale", "roughness_scale", "view_scale", "env_intensity",
 * "env_rotation", "light_intensity", "light_rotation", "rotate", "light", "split" [0, 1],
 * "error_scale" (0, 100]: one value;
 * "light_color": three. Ranges as in the panel; out of range is refused. */
bool dm_viewer_set_param(dm_viewer *v, const char *name, const float *values, int count);
/* --reference (dm_viewer_compare.c). Load after dm_viewer_load and before
 * dm_viewer_start: a texture-space reference sets the irradiance size to its N, a frame
 * reference the picture size to its own; the comparison starts side by side. */
dm_result dm_viewer_compare_load(dm_viewer *v, const char *path, dm_error *err);
/* "off", "side", "split" or "error" (refused without a reference). */
bool dm_viewer_set_compare(dm_viewer *v, const char *mode);
/* Key C: off → side → split → error → off. */
void dm_viewer_cycle_compare(dm_viewer *v);
/* The frame's comparison picture into v->rgba (called by dm_viewer_update). */
bool dm_viewer_compare_frame(dm_viewer *v);
void dm_viewer_compare_free(dm_viewer *v);

/* Subsurface technique (dm_viewer_technique.c): "texture-space", "screen-space" or
 * "pre-integrated"; the renderer is recreated over the same assets (a screen-space kernel
 * missing from the pack is fitted from the profile; texture-space needs the pack's stretch
 * maps, pre-integrated its table and curvature map: refused without, naming them). */
/* What technique t needs that the pack lacks (a phrase), NULL when it can run. */
const char *dm_viewer_technique_missing(const dm_viewer *v, dm_sss_technique t);
bool dm_viewer_set_technique(dm_viewer *v, const char *name);
/* Key T: the next technique the pack supports (texture-space → screen-space →
 * pre-integrated → ...). */
void dm_viewer_cycle_technique(dm_viewer *v);
/* Key shift+T: the other technique beside this one (layout and divider of the comparison:
 * split at cmp.split by default; C cycles side/split/error), with their difference's
 * statistics; refused while a --reference comparison is on. */
bool dm_viewer_set_technique_split(dm_viewer *v, bool on);
/* The frame's technique comparison into v->rgba (called by dm_viewer_update). */
bool dm_viewer_technique_frame(dm_viewer *v, const dm_frame_options *fo);
/* Recreates the renderer for the edited scene, restoring `previous` on failure (what: the
 * status text). */
bool dm_viewer_rebuild(dm_viewer *v, const dm_scene *previous, int previous_irr, const char *what);

/* Screenshot of the rendered image with provenance (view, scene, every parameter). */
bool dm_viewer_screenshot(dm_viewer *v, const char *path);
/* A free name "dermis-view-NNN.png" in the current folder. */
void dm_viewer_next_shot_name(dm_viewer *v, char *out, int size);
/* The current view's name as dm_view_parse reads it ("blur3", "final"). */
void dm_viewer_view_text(const dm_viewer *v, char *out, int size);
/* Every parameter of the picture, as provenance (the same keys as dermis-render plus the
 * viewer's own). */
void dm_viewer_provenance(const dm_viewer *v, dm_provenance *p);
/* --watch: reloads the pack when its file changed (keeping camera and knobs). */
void dm_viewer_watch(dm_viewer *v, double now_ms);
/* Whether the scene is the Lee Perry-Smith head (its attribution must be shown). */
bool dm_viewer_shows_head(const dm_viewer *v);
void dm_viewer_set_status(dm_viewer *v, bool error, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

extern const char dm_viewer_attribution[];
extern const char dm_viewer_help[];

#ifdef __cplusplus
}
#endif
#endif
