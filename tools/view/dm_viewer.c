#include "dm_viewer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "bake/dm_skin_spec.h"
#include "core/dm_cli.h"
#include "core/dm_hash.h"
#include "core/dm_math.h"
#include "render/dm_render_image.h"
#include "render/dm_render_pack.h"
#include "render/dm_render_prov.h"

const char dm_viewer_attribution[] =
    "\"Infinite, 3D Head Scan\" by Lee Perry-Smith (Infinite-Realities), CC BY 3.0";

const char dm_viewer_help[] =
    "left drag      orbit the camera\n"
    "wheel          zoom\n"
    "right/middle   pan\n"
    "shift + left   move the light (the one chosen in the panel)\n"
    "R              rotate the lights around the head (toggle)\n"
    "1 .. 8         toggle specular, subsurface, energy conservation,\n"
    "               shadows, environment lighting, glow, tonemap, translucency\n"
    "T              subsurface technique: the next one the pack supports\n"
    "shift+T        the other technique beside this one (C: side, split, error)\n"
    "B              environment background on/off\n"
    "C              reference comparison: side by side, split, error map, off\n"
    "               (--reference; split position and colour scale in the panel)\n"
    "V / shift+V    next / previous debug view\n"
    "+ / -          exposure +/- 0.5 stop\n"
    "S or F12       screenshot of the picture (PNG with provenance)\n"
    "space          reset the camera\n"
    "Tab            hide/show the panel\n"
    "F1 or H        this help\n"
    "Esc or Q       quit";

/* ---- loading ---------------------------------------------------------------------------- */

static bool file_stamp(const char *path, long long *mtime_ns, long long *size)
{
    struct stat st;
    if (stat(path, &st) != 0) return false;
    *mtime_ns = (long long)st.st_mtim.tv_sec * 1000000000LL + st.st_mtim.tv_nsec;
    *size = (long long)st.st_size;
    return true;
}

/* Opens and verifies a pack, and maps its assets; on failure nothing is left open. */
static dm_result open_pack(const char *path, dm_pack *pack, dm_scene *scene, dm_profile *profile,
                           dm_render_assets *assets, dm_error *err)
{
    dm_result rc = dm_pack_open(path, pack, err);
    if (rc != DM_OK) return rc;
    rc = dm_render_assets_from_pack(pack, scene, profile, assets, err);
    if (rc != DM_OK) dm_pack_close(pack);
    return rc;
}

dm_result dm_viewer_load(dm_viewer *v, const dm_viewer_options *opt, dm_error *err)
{
    memset(v, 0, sizeof *v);
    v->opt = *opt;
    if (opt->pack) {
        dm_result rc = open_pack(opt->pack, &v->pack, &v->loaded, &v->profile, &v->assets, err);
        if (rc != DM_OK) return rc;
        v->pack_open = true;
        v->env_count = dm_render_env_count(&v->pack);
        file_stamp(opt->pack, &v->watch_mtime_ns, &v->watch_size);
    } else {
        dm_synth_options so = {.shape = strcmp(opt->synthetic, "quad") ? DM_SYNTH_SPHERE : DM_SYNTH_QUAD};
        dm_result rc = dm_synth_create(&so, &v->synth, err);
        if (rc != DM_OK) return rc;
        v->loaded = v->synth->scene;
        v->assets = v->synth->assets;
        v->profile = v->synth->scene.profile;
        v->assets.profile = &v->profile;
    }
    v->scene = v->loaded;
    v->assets.scene = &v->scene;
    dm_viewer_camera_from_scene(v);
    dm_viewer_skin_init(v);
    v->view = opt->view;
    v->view_index = opt->view_index;
    v->view_scale = opt->view_scale > 0 ? opt->view_scale : 1;
    v->blur_scale = 1;
    v->roughness_scale = 1;
    v->light_rotation_deg = opt->light_azimuth_deg;
    v->rotate_deg_per_s = 30;
    v->irradiance_size = opt->irradiance_size > 0 ? opt->irradiance_size : 512;
    v->show_panel = true;
    v->dirty = true;
    return DM_OK;
}

/* ---- renderer ------------------------------------------------------------------------- */

dm_result dm_viewer_start(dm_viewer *v, dm_error *err)
{
    if (v->opt.width <= 0 || v->opt.height <= 0) v->opt.width = v->scene.width, v->opt.height = v->scene.height;
    v->rgba = calloc((size_t)v->opt.width * v->opt.height * 4, 1);
    if (!v->rgba) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "cannot allocate the %dx%d display", v->opt.width,
                                 v->opt.height);
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, v->opt.width, v->opt.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    v->tex = t;
    return dm_viewer_create_renderer(v, err);
}

void dm_viewer_free(dm_viewer *v)
{
    dm_viewer_compare_free(v);
    dm_renderer_destroy(v->r_other);
    dm_renderer_destroy(v->r);
    if (v->tex) {
        GLuint t = v->tex;
        glDeleteTextures(1, &t);
    }
    free(v->rgba);
    if (v->pack_open) dm_pack_close(&v->pack);
    dm_synth_free(v->synth);
    memset(v, 0, sizeof *v);
}

void dm_viewer_view_text(const dm_viewer *v, char *out, int size)
{
    const char *n = dm_view_name(v->view);
    if (v->view == DM_VIEW_BLUR || v->view == DM_VIEW_STRETCH || v->view == DM_VIEW_SHADOW)
        snprintf(out, (size_t)size, "%s%d", n, v->view_index);
    else
        snprintf(out, (size_t)size, "%s", n ? n : "final");
}

void dm_viewer_update(dm_viewer *v, double dt_s)
{
    if (v->light_rotating) {
        v->light_rotation_deg = fmodf(v->light_rotation_deg + (float)(v->rotate_deg_per_s * dt_s), 360.0f);
        v->dirty = true;
    }
    if (!v->dirty || !v->r) return;
    v->dirty = false;
    dm_error err = {0};
    dm_viewer_apply_camera(v);
    if (dm_renderer_set_scene(v->r, &v->scene, &err) != DM_OK) {
        dm_scene prev = v->scene;
        if (!dm_viewer_rebuild(v, &prev, v->irradiance_size, "scene change")) return;
    }
    dm_frame_options fo = {.view = v->view, .view_index = v->view_index, .view_scale = v->view_scale,
                           .light_rotation_deg = v->light_rotation_deg, .blur_scale = v->blur_scale,
                           .roughness_scale = v->roughness_scale};
    if (v->cmp.on) { /* the view the reference matches, unscaled */
        fo.view = v->cmp.ref.mode == DM_REFCMP_TEXTURE_SPACE ? DM_VIEW_DIFFUSION : DM_VIEW_FINAL;
        fo.view_index = 0, fo.view_scale = 1;
    } else if (v->tsplit) { /* two techniques: the final pictures */
        fo.view = DM_VIEW_FINAL, fo.view_index = 0, fo.view_scale = 1;
    }
    if (dm_render_frame(v->r, &fo, &err) != DM_OK) {
        dm_viewer_set_status(v, true, "frame: %s", err.detail);
        if (v->view != DM_VIEW_FINAL) {
            v->view = DM_VIEW_FINAL, v->view_index = 0;
            v->dirty = true;
        }
        return;
    }
    dm_renderer_last_timings(v->r, v->pass_ms, &v->frame_ms);
    if (v->cmp.on) {
        if (!dm_viewer_compare_frame(v)) return;
    } else if (v->tsplit) {
        if (!dm_viewer_technique_frame(v, &fo)) return;
    } else if (dm_renderer_read_display(v->r, v->rgba, &err) != DM_OK) {
        dm_viewer_set_status(v, true, "read back: %s", err.detail);
        return;
    }
    glBindTexture(GL_TEXTURE_2D, v->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, v->opt.width, v->opt.height, GL_RGBA, GL_UNSIGNED_BYTE, v->rgba);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        v->gl_errors++;
        dm_viewer_set_status(v, true, "GL error 0x%04x after the frame", (unsigned)e);
    }
    v->frames++;
}

/* ---- actions -------------------------------------------------------------------------- */

bool dm_viewer_set_effect(dm_viewer *v, dm_effect e, bool on)
{
    if (v->scene.effects[e] == on) return true;
    dm_scene prev = v->scene;
    v->scene.effects[e] = on;
    char what[96];
    snprintf(what, sizeof what, "%s %s", dm_effect_name(e), on ? "on" : "off");
    bool ok = dm_viewer_rebuild(v, &prev, v->irradiance_size, what);
    /* a view the new pass list cannot show falls back to the final picture */
    dm_render_plan plan;
    dm_error err = {0};
    if (dm_render_plan_build(&v->scene, v->view, v->view_index, &plan, &err) != DM_OK)
        v->view = DM_VIEW_FINAL, v->view_index = 0;
    return ok;
}

bool dm_viewer_set_background(dm_viewer *v, bool on)
{
    if (v->scene.env_background == on) return true;
    dm_scene prev = v->scene;
    v->scene.env_background = on;
    return dm_viewer_rebuild(v, &prev, v->irradiance_size, on ? "background on" : "background off");
}

bool dm_viewer_set_irradiance(dm_viewer *v, int size)
{
    if (size < 8 || size > 8192) {
        dm_viewer_set_status(v, true, "irradiance size %d is not in [8, 8192]", size);
        return false;
    }
    if (size == v->irradiance_size) return true;
    int prev = v->irradiance_size;
    dm_scene prev_scene = v->scene;
    v->irradiance_size = size;
    char what[64];
    snprintf(what, sizeof what, "irradiance %d", size);
    return dm_viewer_rebuild(v, &prev_scene, prev, what);
}

/* Points v->assets at packed environment k and names its map in the edited scene. */
static dm_result assets_for_env(dm_viewer *v, int k, dm_error *err)
{
    dm_scene scene;
    dm_profile profile;
    dm_render_assets a;
    dm_result rc = dm_render_assets_from_pack_env(&v->pack, k, &scene, &profile, &a, err);
    if (rc != DM_OK) return rc;
    a.scene = &v->scene;
    a.profile = &v->profile;
    v->assets = a;
    v->env = k;
    snprintf(v->scene.environment, sizeof v->scene.environment, "%s",
             k == 0 ? v->loaded.environment : v->loaded.env_alternatives[k - 1]);
    return DM_OK;
}

bool dm_viewer_set_env(dm_viewer *v, int k)
{
    if (!v->pack_open || k < 0 || k >= v->env_count) {
        dm_viewer_set_status(v, true, "environment %d is not in [0, %d] (the %s holds %d)", k,
                             v->env_count > 0 ? v->env_count - 1 : 0, v->pack_open ? "pack" : "synthetic scene",
                             v->env_count);
        return false;
    }
    if (k == v->env) return true;
    int prev = v->env;
    dm_error err = {0};
    char name[256], what[300];
    dm_viewer_env_name(v, k, name, (int)sizeof name);
    snprintf(what, sizeof what, "environment %d (%s)", k, name);
    if (assets_for_env(v, k, &err) == DM_OK && dm_viewer_create_renderer(v, &err) == DM_OK) {
        dm_viewer_set_status(v, false, "%s", what);
        return true;
    }
    char why[sizeof err.detail];
    snprintf(why, sizeof why, "%s", err.detail);
    dm_error err2 = {0};
    if (assets_for_env(v, prev, &err2) != DM_OK || dm_viewer_create_renderer(v, &err2) != DM_OK)
        fprintf(stderr, "error: cannot restore the renderer: %s\n", err2.detail);
    dm_viewer_set_status(v, true, "%s refused: %s", what, why);
    return false;
}

void dm_viewer_env_name(const dm_viewer *v, int k, char *out, int size)
{
    if (v->pack_open) {
        dm_render_env_name(&v->pack, &v->loaded, k, out, (size_t)size);
    } else {
        const char *slash = strrchr(v->loaded.environment, '/');
        snprintf(out, (size_t)size, "%s", slash ? slash + 1 : v->loaded.environment);
    }
}

bool dm_viewer_set_view(dm_viewer *v, const char *name)
{
    dm_view view;
    int k;
    dm_render_plan plan;
    dm_error err = {0};
    if (!dm_view_parse(name, &view, &k)) {
        dm_viewer_set_status(v, true, "view '%s' is not a view name", name);
        return false;
    }
    if (dm_render_plan_build(&v->scene, view, k, &plan, &err) != DM_OK) {
        dm_viewer_set_status(v, true, "view %s: %s", name, err.detail);
        return false;
    }
    v->view = view, v->view_index = k;
    v->dirty = true;
    return true;
}

bool dm_viewer_cycle_view(dm_viewer *v, int step)
{
    if (v->view_count == 0) return false;
    char cur[16];
    dm_viewer_view_text(v, cur, sizeof cur);
    int at = 0;
    for (int i = 0; i < v->view_count; ++i)
        if (!strcmp(v->view_names[i], cur)) at = i;
    at = ((at + step) % v->view_count + v->view_count) % v->view_count;
    return dm_viewer_set_view(v, v->view_names[at]);
}

static bool in_range(dm_viewer *v, const char *name, float x, float lo, float hi)
{
    if (isfinite(x) && x >= lo && x <= hi) return true;
    dm_viewer_set_status(v, true, "%s: %g is not in [%g, %g]", name, (double)x, (double)lo, (double)hi);
    return false;
}

bool dm_viewer_set_param(dm_viewer *v, const char *name, const float *x, int count)
{
    dm_light *l = v->scene.light_count ? &v->scene.lights[v->light] : NULL;
    if (!strcmp(name, "light_color")) {
        if (count != 3 || !l) return dm_viewer_set_status(v, true, "light_color needs 3 values and a light"), false;
        for (int k = 0; k < 3; ++k)
            if (!in_range(v, name, x[k], 0, 1e6f)) return false;
        memcpy(l->color, x, sizeof l->color);
        v->dirty = true;
        return true;
    }
    if (count != 1) return dm_viewer_set_status(v, true, "%s takes one value", name), false;
    float a = x[0];
    if (!strcmp(name, "melanin") || !strcmp(name, "blood") || !strcmp(name, "epidermis"))
        return dm_viewer_skin_set(v, name, a);
    if (!strcmp(name, "exposure")) {
        if (!in_range(v, name, a, -20, 20)) return false;
        v->scene.exposure = a;
    } else if (!strcmp(name, "mix")) {
        if (!in_range(v, name, a, 0, 1)) return false;
        v->scene.mix = a;
    } else if (!strcmp(name, "blur_scale")) {
        if (!in_range(v, name, a, 0.01f, 100)) return false;
        v->blur_scale = a;
    } else if (!strcmp(name, "roughness_scale")) {
        if (!in_range(v, name, a, 0.01f, 10)) return false;
        v->roughness_scale = a;
    } else if (!strcmp(name, "view_scale")) {
        if (!in_range(v, name, a, 1e-6f, 1e6f)) return false;
        v->view_scale = a;
    } else if (!strcmp(name, "env_intensity")) {
        if (!in_range(v, name, a, 0, 1e6f)) return false;
        v->scene.env_intensity = a;
    } else if (!strcmp(name, "env_rotation")) {
        if (!in_range(v, name, a, -360, 360)) return false;
        v->scene.env_rotation_deg = a;
    } else if (!strcmp(name, "light_intensity")) {
        if (!l || !in_range(v, name, a, 0, 1e6f)) return false;
        l->intensity = a;
    } else if (!strcmp(name, "light_rotation")) {
        if (!in_range(v, name, a, -360, 360)) return false;
        v->light_rotation_deg = a;
    } else if (!strcmp(name, "rotate")) {
        v->light_rotating = a != 0;
    } else if (!strcmp(name, "split")) {
        if (!in_range(v, name, a, 0, 1)) return false;
        v->cmp.split = a;
    } else if (!strcmp(name, "error_scale")) {
        if (!in_range(v, name, a, 1e-6f, 100)) return false;
        v->cmp.error_scale = a;
    } else if (!strcmp(name, "light")) {
        if (!in_range(v, name, a, 0, (float)(v->scene.light_count - 1)) || a != floorf(a)) return false;
        v->light = (int)a;
    } else {
        dm_viewer_set_status(v, true, "'%s' is not a parameter (see --help)", name);
        return false;
    }
    v->dirty = true;
    return true;
}

/* ---- output --------------------------------------------------------------------------- */

void dm_viewer_provenance(const dm_viewer *v, dm_provenance *p)
{
    const dm_scene *s = &v->scene;
    char hash[DM_HASH_HEX_SIZE] = "";
    if (v->opt.pack) {
        dm_error err = {0};
        if (dm_hash_file_hex(v->opt.pack, hash, &err) != DM_OK) hash[0] = '\0';
    }
    char view[16];
    dm_viewer_view_text(v, view, sizeof view);
    /* the keys of dermis-render first, so the two tools' files compare key by key */
    dm_render_provenance(p, "dermis-view", v->opt.pack ? v->opt.pack : v->opt.synthetic ? v->opt.synthetic : "", hash,
                         s, v->r, view, v->light_rotation_deg, 1);
    /* the viewer's own knobs */
    dm_prov_add_double(p, "view_scale", v->view_scale);
    dm_prov_add_double(p, "blur_scale", v->blur_scale);
    dm_prov_add_double(p, "roughness_scale", v->roughness_scale);
    dm_prov_add_double(p, "roughness", s->roughness);
    dm_prov_add_double(p, "rho_s", s->rho_s);
    dm_prov_add_string(p, "environment", s->environment);
    dm_prov_add_double(p, "env_intensity", s->env_intensity);
    dm_prov_add_double(p, "env_rotation_deg", s->env_rotation_deg);
    dm_prov_add_int(p, "env_background", s->env_background);
    dm_prov_add_int(p, "env_index", v->env);
    if (v->skin.changed) { /* the live skin: its parameters and the colour scale it applies */
        char spec[512];
        dm_skin_spec_format(&v->skin.now, 17, spec, sizeof spec);
        dm_prov_add_string(p, "skin", spec);
        for (int c = 0; c < 3; ++c) {
            char key[16];
            snprintf(key, sizeof key, "skin_scale_%c", "rgb"[c]);
            dm_prov_add_double(p, key, v->skin.scale_rgb[c]);
        }
    }
    dm_prov_add_double(p, "glow_threshold", s->glow_threshold);
    dm_prov_add_double(p, "glow_intensity", s->glow_intensity);
    for (int i = 0; i < s->light_count && i < 8; ++i) {
        const dm_light *l = &s->lights[i];
        const float *d = l->type == DM_LIGHT_DIRECTIONAL ? l->direction : l->position;
        char key[24], val[256];
        snprintf(key, sizeof key, "light%d", i);
        snprintf(val, sizeof val, "%s %g %g %g color %g %g %g intensity %g shadow %d",
                 dm_light_type_name(l->type), (double)d[0], (double)d[1], (double)d[2], (double)l->color[0],
                 (double)l->color[1], (double)l->color[2], (double)l->intensity, (int)l->casts_shadow);
        dm_prov_add_string(p, key, val);
    }
}

bool dm_viewer_screenshot(dm_viewer *v, const char *path)
{
    if (v->frames == 0) return dm_viewer_set_status(v, true, "%s: no frame rendered yet", path), false;
    dm_provenance prov;
    dm_viewer_provenance(v, &prov);
    dm_error err = {0}; /* a frame holding NaN or Inf is not written (dm_renderer_check_finite) */
    if (dm_renderer_check_finite(v->r, &err) != DM_OK ||
        dm_render_write_png(path, v->opt.width, v->opt.height, v->rgba, &prov, &err) != DM_OK) {
        dm_viewer_set_status(v, true, "%s", err.detail);
        return false;
    }
    char view[16];
    dm_viewer_view_text(v, view, sizeof view);
    dm_viewer_set_status(v, false, "wrote %s", path);
    if (!v->opt.quiet) printf("wrote %s (%dx%d, view %s)\n", path, v->opt.width, v->opt.height, view);
    fflush(stdout);
    return true;
}

void dm_viewer_next_shot_name(dm_viewer *v, char *out, int size)
{
    for (;;) {
        char name[32];
        snprintf(name, sizeof name, "dermis-view-%03d.png", v->shot_count++ % 1000);
        snprintf(out, (size_t)size, "%s", name);
        struct stat st;
        if (stat(out, &st) != 0 || v->shot_count > 999) return;
    }
}

bool dm_viewer_shows_head(const dm_viewer *v)
{
    return strstr(v->scene.mesh, "LeePerrySmith") != NULL || strstr(v->scene.albedo, "lps/") != NULL;
}

void dm_viewer_watch(dm_viewer *v, double now_ms)
{
    if (!v->opt.watch || !v->opt.pack || now_ms < v->watch_next_ms) return;
    v->watch_next_ms = now_ms + 500;
    long long mt, sz;
    if (!file_stamp(v->opt.pack, &mt, &sz) || (mt == v->watch_mtime_ns && sz == v->watch_size)) return;
    v->watch_mtime_ns = mt, v->watch_size = sz;
    dm_pack pack;
    dm_scene scene;
    dm_profile profile;
    dm_render_assets assets;
    dm_error err = {0};
    if (open_pack(v->opt.pack, &pack, &scene, &profile, &assets, &err) != DM_OK) {
        dm_viewer_set_status(v, false, "reload kept the previous pack: %s", err.detail);
        fprintf(stderr, "warning: reload kept the previous pack: %s\n", err.detail);
        return;
    }
    /* swap in the new pack, keeping the camera and the per-frame knobs */
    dm_renderer_destroy(v->r);
    v->r = NULL;
    if (v->pack_open) dm_pack_close(&v->pack);
    v->pack = pack;
    v->pack_open = true;
    v->loaded = scene;
    v->profile = profile;
    float eye[3], target[3], up[3];
    memcpy(eye, v->scene.camera_eye, sizeof eye);
    memcpy(target, v->scene.camera_target, sizeof target);
    memcpy(up, v->scene.camera_up, sizeof up);
    v->scene = scene;
    memcpy(v->scene.camera_eye, eye, sizeof eye);
    memcpy(v->scene.camera_target, target, sizeof target);
    memcpy(v->scene.camera_up, up, sizeof up);
    v->assets = assets;
    v->assets.profile = &v->profile;
    v->assets.scene = &v->scene;
    dm_viewer_skin_init(v); /* the new pack's skin and variances */
    v->env_count = dm_render_env_count(&v->pack);
    int env = v->env;
    v->env = 0;
    if (env > 0 && env < v->env_count && assets_for_env(v, env, &err) != DM_OK)
        fprintf(stderr, "warning: reload shows the main environment: %s\n", err.detail);
    if (dm_viewer_create_renderer(v, &err) != DM_OK) {
        dm_viewer_set_status(v, true, "reload: %s", err.detail);
        return;
    }
    dm_viewer_set_status(v, false, "reloaded %s", v->opt.pack);
    if (!v->opt.quiet) printf("reloaded %s\n", v->opt.pack);
}
