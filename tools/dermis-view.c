/* dermis-view — the interactive viewer: a GLFW window over the same lib/render core as
 * dermis-render, with a panel (Dear ImGui behind tools/view/dm_viewer_ui.h).
 * Straight pipeline: parse → load (pack verified, or synthetic) → window + renderer →
 * event loop (render on demand) → exit code. --script replays timed input for tests. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "core/dm_cli.h"
#include "core/dm_png.h"
#include "view/dm_glfw.h"
#include "view/dm_viewer.h"
#include "view/dm_viewer_script.h"
#include "view/dm_viewer_ui.h"

static void usage(FILE *f)
{
    fprintf(f,
            "Usage: dermis-view PACK [--size WxH] [--watch] [options]\n"
            "       dermis-view --synthetic sphere|quad [options]\n"
            "Shows a pack interactively (GLFW window, OpenGL 3.3 core) through the texture-space skin\n"
            "pipeline, with a panel for lights, effects, debug views, environment and timings.\n"
            "\n"
            "  --synthetic SHAPE    show the built-in synthetic scene instead of a pack\n"
            "  --size WxH           window and picture size, default the scene's (1280x720); 64..8192\n"
            "  --irradiance N       texture-space irradiance size, default 512 (the scene's 1024 costs\n"
            "                       ~4x on software GL); 8..8192 (~300 bytes a texel on software GL:\n"
            "                       8192 needs ~19 GiB; sizes beyond the OpenGL's limits or the memory\n"
            "                       available are refused, naming both: docs/dermis-render.md, Memory)\n"
            "  --view NAME          first debug view: final (default), irradiance, blurK, stretchK,\n"
            "                       shadowK, specular, diffuse, uv, wireframe\n"
            "  --view-scale X       multiplies debug texture views, default 1; (0, 1e6]\n"
            "  --light-azimuth DEG  turns every light about +Y, default 0; [-360, 360]\n"
            "  --reference REF.exr  compare with a ground truth (dermis-reference): texture-space\n"
            "                       references against the diffusion view at irradiance size N, frame\n"
            "                       references against the final linear image at their size (the\n"
            "                       window takes it); side by side, split or error map (key C, panel)\n"
            "  --watch              reload the pack when its file changes, keeping the camera\n"
            "  --script FILE        replay timed input events and screenshots, then exit (format in\n"
            "                       docs/dermis-view.md); exit code 3 if any event or GL call failed\n"
            "  --shader-dir DIR     load shaders from DIR/*.glsl instead of the embedded copies\n"
            "  -v                   more detail on stderr\n"
            "  --quiet              nothing on stdout\n"
            "  -h, --help           this text\n"
            "Keys: F1 in the window lists them (orbit: left drag, zoom: wheel, pan: right/middle drag).\n"
            "Exit codes: 0 success, 1 usage error, 2 cannot load the input (missing, unusable or\n"
            "            corrupt pack: the validator's message, as dermis-check prints it),\n"
            "            3 no display / no OpenGL 3.3 / rendering or a script event failed,\n"
            "            4 cannot save a screenshot.\n");
}

typedef struct options {
    dm_viewer_options v;
    const char *script, *reference;
} options;

static int parse(int argc, char **argv, options *o)
{
    memset(o, 0, sizeof *o);
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *val = NULL;
        int64_t n;
        double d;
        if (dm_cli_version(a, "dermis-view")) exit(0);
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            exit(DM_EXIT_OK);
        } else if (!strcmp(a, "--synthetic")) {
            if (!(o->v.synthetic = dm_cli_value(argc, argv, &i))) return 0;
            if (strcmp(o->v.synthetic, "sphere") && strcmp(o->v.synthetic, "quad")) {
                fprintf(stderr, "error: --synthetic: '%s' is not sphere or quad\n", o->v.synthetic);
                return 0;
            }
        } else if (!strcmp(a, "--size")) {
            if (!(val = dm_cli_value(argc, argv, &i))) return 0;
            int w = 0, h = 0;
            char tail = 0;
            if (sscanf(val, "%dx%d%c", &w, &h, &tail) != 2 || w < 64 || h < 64 || w > 8192 || h > 8192) {
                fprintf(stderr, "error: --size: '%s' is not WxH with sides in [64, 8192]\n", val);
                return 0;
            }
            o->v.width = w, o->v.height = h;
        } else if (!strcmp(a, "--irradiance")) {
            if (!(val = dm_cli_value(argc, argv, &i)) || !dm_cli_int(a, val, 8, 8192, &n)) return 0;
            o->v.irradiance_size = (int)n;
        } else if (!strcmp(a, "--view")) {
            if (!(val = dm_cli_value(argc, argv, &i))) return 0;
            if (!dm_view_parse(val, &o->v.view, &o->v.view_index)) {
                fprintf(stderr, "error: --view: '%s' is not a view (see --help)\n", val);
                return 0;
            }
        } else if (!strcmp(a, "--view-scale")) {
            if (!(val = dm_cli_value(argc, argv, &i)) || !dm_cli_double(a, val, 1e-12, 1e6, &d)) return 0;
            o->v.view_scale = (float)d;
        } else if (!strcmp(a, "--light-azimuth")) {
            if (!(val = dm_cli_value(argc, argv, &i)) || !dm_cli_double(a, val, -360, 360, &d)) return 0;
            o->v.light_azimuth_deg = (float)d;
        } else if (!strcmp(a, "--watch")) {
            o->v.watch = true;
        } else if (!strcmp(a, "--reference")) {
            if (!(o->reference = dm_cli_value(argc, argv, &i))) return 0;
        } else if (!strcmp(a, "--script")) {
            if (!(o->script = dm_cli_value(argc, argv, &i))) return 0;
        } else if (!strcmp(a, "--shader-dir")) {
            if (!(o->v.shader_dir = dm_cli_value(argc, argv, &i))) return 0;
        } else if (!strcmp(a, "-v")) {
            o->v.verbose = true;
        } else if (!strcmp(a, "--quiet")) {
            o->v.quiet = true;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "error: unknown option '%s'\n", a);
            return 0;
        } else if (!o->v.pack) {
            o->v.pack = a;
        } else {
            fprintf(stderr, "error: unexpected argument '%s' (one PACK only)\n", a);
            return 0;
        }
    }
    if (!!o->v.pack == !!o->v.synthetic) {
        fprintf(stderr, "error: give either a PACK or --synthetic SHAPE\n");
        return 0;
    }
    if (o->v.watch && o->v.synthetic) {
        fprintf(stderr, "error: --watch needs a PACK file, not --synthetic\n");
        return 0;
    }
    if (o->v.verbose && o->v.quiet) {
        fprintf(stderr, "error: -v and --quiet conflict\n");
        return 0;
    }
    return 1;
}

/* ---- input: window callbacks and script events go through the same handlers ---------- */

typedef struct app {
    dm_viewer v;
    GLFWwindow *window;
    bool button[3];
    bool shift;
    double x, y;
    dm_script script;
    bool scripted;
    char window_shot[1024];
    int window_shot_wait; /* UI frames to draw before capturing (ImGui lays out over two) */
    int save_failures;
} app;

static void handle_key(app *a, int key, int mods)
{
    dm_viewer *v = &a->v;
    bool shift = (mods & GLFW_MOD_SHIFT) != 0;
    if (key >= GLFW_KEY_1 && key <= GLFW_KEY_8) {
        dm_effect e = (dm_effect)(key - GLFW_KEY_1);
        dm_viewer_set_effect(v, e, !v->scene.effects[e]);
        return;
    }
    switch (key) {
    case GLFW_KEY_F1:
    case GLFW_KEY_H: v->show_help = !v->show_help; break;
    case GLFW_KEY_TAB:
        v->show_panel = !v->show_panel;
        v->dirty |= v->cmp.on; /* the comparison legend keeps clear of the panel */
        break;
    case GLFW_KEY_R: v->light_rotating = !v->light_rotating; break;
    case GLFW_KEY_B: dm_viewer_set_background(v, !v->scene.env_background); break;
    case GLFW_KEY_C: dm_viewer_cycle_compare(v); break;
    case GLFW_KEY_T:
        if (shift) dm_viewer_set_technique_split(v, !v->tsplit);
        else dm_viewer_cycle_technique(v);
        break;
    case GLFW_KEY_V: dm_viewer_cycle_view(v, shift ? -1 : 1); break;
    case GLFW_KEY_SPACE: dm_viewer_reset_camera(v); break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD: {
        float x = v->scene.exposure + 0.5f;
        dm_viewer_set_param(v, "exposure", &x, 1);
        break;
    }
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT: {
        float x = v->scene.exposure - 0.5f;
        dm_viewer_set_param(v, "exposure", &x, 1);
        break;
    }
    case GLFW_KEY_S:
    case GLFW_KEY_F12: {
        char name[64];
        dm_viewer_next_shot_name(v, name, sizeof name);
        if (!dm_viewer_screenshot(v, name)) a->save_failures++;
        break;
    }
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q: v->quit = true; break;
    default: break;
    }
}

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    (void)scancode;
    app *a = glfwGetWindowUserPointer(w);
    if (action == GLFW_RELEASE || dm_ui_wants_keyboard()) return;
    if (action == GLFW_REPEAT && key != GLFW_KEY_EQUAL && key != GLFW_KEY_MINUS && key != GLFW_KEY_KP_ADD &&
        key != GLFW_KEY_KP_SUBTRACT)
        return;
    handle_key(a, key, mods);
}

static void on_button(GLFWwindow *w, int button, int action, int mods)
{
    app *a = glfwGetWindowUserPointer(w);
    if (button < 0 || button > 2) return;
    if (action == GLFW_PRESS && dm_ui_wants_mouse()) return;
    a->button[button] = action == GLFW_PRESS;
    a->shift = (mods & GLFW_MOD_SHIFT) != 0;
    glfwGetCursorPos(w, &a->x, &a->y);
}

/* one drag step: left orbits (shift+left moves the light), right and middle pan */
static void drag(app *a, int button, bool shift, float dx, float dy)
{
    if (button == GLFW_MOUSE_BUTTON_LEFT && shift) dm_viewer_drag_light(&a->v, dx, dy);
    else if (button == GLFW_MOUSE_BUTTON_LEFT) dm_viewer_orbit(&a->v, dx, dy);
    else dm_viewer_pan(&a->v, dx, dy);
}

static void on_cursor(GLFWwindow *w, double x, double y)
{
    app *a = glfwGetWindowUserPointer(w);
    float dx = (float)(x - a->x), dy = (float)(y - a->y);
    a->x = x, a->y = y;
    for (int b = 0; b < 3; ++b)
        if (a->button[b]) drag(a, b, a->shift, dx, dy);
}

static void on_scroll(GLFWwindow *w, double xoff, double yoff)
{
    (void)xoff;
    if (dm_ui_wants_mouse()) return;
    app *a = glfwGetWindowUserPointer(w);
    dm_viewer_zoom(&a->v, (float)yoff);
}

static int key_from_name(const char *name, int *mods)
{
    static const struct {
        const char *name;
        int key;
    } keys[] = {{"F1", GLFW_KEY_F1},       {"F12", GLFW_KEY_F12},     {"H", GLFW_KEY_H},
                {"S", GLFW_KEY_S},         {"R", GLFW_KEY_R},         {"B", GLFW_KEY_B},
                {"V", GLFW_KEY_V},         {"Q", GLFW_KEY_Q},         {"C", GLFW_KEY_C},         {"TAB", GLFW_KEY_TAB}, {"T", GLFW_KEY_T},
                {"SPACE", GLFW_KEY_SPACE}, {"ESCAPE", GLFW_KEY_ESCAPE}, {"PLUS", GLFW_KEY_EQUAL},
                {"MINUS", GLFW_KEY_MINUS}};
    *mods = 0;
    if (!strncmp(name, "shift+", 6)) *mods = GLFW_MOD_SHIFT, name += 6;
    if (name[0] >= '1' && name[0] <= '8' && !name[1]) return GLFW_KEY_1 + (name[0] - '1');
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; ++i)
        if (!strcmp(name, keys[i].name)) return keys[i].key;
    return -1;
}

/* Runs one script event; returns false when it failed (the viewer already said why). */
static bool run_event(app *a, const dm_script_event *e)
{
    dm_viewer *v = &a->v;
    const char *c = e->command;
    int before = v->failures;
    if (!strcmp(c, "key")) {
        int mods, key = key_from_name(e->args[0], &mods);
        if (key < 0) {
            dm_viewer_set_status(v, true, "%s:%d: '%s' is not a key name", a->script.path, e->line, e->args[0]);
            return false;
        }
        handle_key(a, key, mods);
    } else if (!strcmp(c, "drag")) {
        float x0 = strtof(e->args[0], NULL), y0 = strtof(e->args[1], NULL);
        float x1 = strtof(e->args[2], NULL), y1 = strtof(e->args[3], NULL);
        const char *b = e->arg_count > 4 ? e->args[4] : "left";
        int button = !strcmp(b, "right") ? GLFW_MOUSE_BUTTON_RIGHT
                     : !strcmp(b, "middle") ? GLFW_MOUSE_BUTTON_MIDDLE : GLFW_MOUSE_BUTTON_LEFT;
        /* in 8 steps, as the cursor callback would see it */
        for (int s = 0; s < 8; ++s) drag(a, button, !strcmp(b, "light"), (x1 - x0) / 8, (y1 - y0) / 8);
    } else if (!strcmp(c, "scroll")) {
        dm_viewer_zoom(v, strtof(e->args[0], NULL));
    } else if (!strcmp(c, "toggle")) {
        const char *name = e->args[0];
        bool has = e->arg_count > 1;
        if (has && strcmp(e->args[1], "on") && strcmp(e->args[1], "off")) {
            dm_viewer_set_status(v, true, "%s:%d: toggle: '%s' is not on or off", a->script.path, e->line,
                                 e->args[1]);
            return false;
        }
        bool want_on = has && !strcmp(e->args[1], "on");
        if (!strcmp(name, "background")) {
            dm_viewer_set_background(v, has ? want_on : !v->scene.env_background);
        } else {
            int fx = dm_effect_from_name(name);
            if (fx < 0) {
                dm_viewer_set_status(v, true, "%s:%d: '%s' is not an effect", a->script.path, e->line, name);
                return false;
            }
            dm_viewer_set_effect(v, (dm_effect)fx, has ? want_on : !v->scene.effects[fx]);
        }
    } else if (!strcmp(c, "view")) {
        dm_viewer_set_view(v, e->args[0]);
    } else if (!strcmp(c, "set")) {
        float x[3] = {0, 0, 0};
        for (int k = 1; k < e->arg_count; ++k) x[k - 1] = strtof(e->args[k], NULL);
        if (!strcmp(e->args[0], "irradiance")) dm_viewer_set_irradiance(v, (int)x[0]);
        else dm_viewer_set_param(v, e->args[0], x, e->arg_count - 1);
    } else if (!strcmp(c, "env")) {
        double k = strtod(e->args[0], NULL);
        if (k != floor(k)) {
            dm_viewer_set_status(v, true, "%s:%d: env: '%s' is not an environment index", a->script.path, e->line,
                                 e->args[0]);
            return false;
        }
        dm_viewer_set_env(v, (int)k);
    } else if (!strcmp(c, "compare")) {
        dm_viewer_set_compare(v, e->args[0]);
    } else if (!strcmp(c, "technique")) { /* NAME, or split / nosplit */
        if (!strcmp(e->args[0], "split") || !strcmp(e->args[0], "nosplit"))
            dm_viewer_set_technique_split(v, e->args[0][0] == 's');
        else
            dm_viewer_set_technique(v, e->args[0]);
    } else if (!strcmp(c, "screenshot")) {
        if (!dm_viewer_screenshot(v, e->args[0])) a->save_failures++;
    } else if (!strcmp(c, "window-shot")) {
        snprintf(a->window_shot, sizeof a->window_shot, "%s", e->args[0]);
        a->window_shot_wait = 2;
    } else if (!strcmp(c, "quit")) {
        v->quit = true;
    }
    if (v->failures > before) fprintf(stderr, "  (script %s:%d: %s)\n", a->script.path, e->line, c);
    return v->failures == before;
}

/* Runs the events that are due; a screenshot, window-shot or quit waits until the frame
 * showing every earlier event is done. */
static void run_script(app *a, double elapsed_s)
{
    dm_script *s = &a->script;
    while (s->next < s->count && !a->window_shot[0]) {
        const dm_script_event *e = &s->events[s->next];
        if (e->time_s > elapsed_s) return;
        bool waits = !strcmp(e->command, "screenshot") || !strcmp(e->command, "window-shot") ||
                     !strcmp(e->command, "quit");
        if (waits && a->v.dirty) return;
        s->next++;
        run_event(a, e);
    }
    if (s->next == s->count && !a->window_shot[0] && !a->v.dirty) a->v.quit = true;
}

static void capture_window(app *a)
{
    int w, h;
    glfwGetFramebufferSize(a->window, &w, &h);
    uint8_t *px = malloc((size_t)w * h * 4);
    dm_error err = {0};
    dm_provenance prov;
    dm_viewer_provenance(&a->v, &prov);
    dm_prov_add_string(&prov, "capture", "window with panel");
    if (px) {
        glReadBuffer(GL_BACK);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, px);
        for (size_t i = 0; i < (size_t)w * h; ++i) px[i * 4 + 3] = 255;
    }
    if (!px || dm_png_write_pixels(a->window_shot, w, h, 4, 8, px, &prov, NULL, 0, &err) != DM_OK) {
        dm_viewer_set_status(&a->v, true, "%s: %s", a->window_shot, px ? err.detail : "out of memory");
        a->save_failures++;
    } else if (!a->v.opt.quiet) {
        printf("wrote %s (%dx%d, window with panel)\n", a->window_shot, w, h);
        fflush(stdout);
    }
    free(px);
    a->window_shot[0] = 0;
}

int main(int argc, char **argv)
{
    options o;
    if (!parse(argc, argv, &o)) {
        fprintf(stderr, "Usage: dermis-view PACK [--size WxH] [--watch] [options] (--help for all)\n");
        return DM_EXIT_USAGE;
    }
    dm_error err = {0};
    app *a = calloc(1, sizeof *a);
    if (!a) return DM_EXIT_PROCESS;

    /* load: the script and the pack are checked before any window opens */
    if (o.script) { /* a script that cannot be read: 2; one that is wrong: 1 (its lines say "error:") */
        int bad = dm_script_read(o.script, &a->script, &err) == DM_OK              ? 0
                  : err.code == DM_ERR_FILE_OPEN || err.code == DM_ERR_FILE_READ ? DM_EXIT_LOAD
                                                                                 : DM_EXIT_USAGE;
        if (bad) fprintf(stderr, "%s%s\n", bad == DM_EXIT_LOAD ? "error: " : "", err.detail);
        if (bad || (bad = dm_script_check_outputs(&a->script, (const char *const[]){o.v.pack, o.reference, o.script}, 3))) {
            dm_script_free(&a->script);
            free(a);
            return bad;
        }
        a->scripted = true;
    }
    if (dm_viewer_load(&a->v, &o.v, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        /* missing, unusable or corrupt (the validator's message): cannot load the input,
         * exit 2 as in dermis-render */
        dm_script_free(&a->script);
        dm_viewer_free(&a->v);
        free(a);
        return DM_EXIT_LOAD;
    }

    if (o.reference && dm_viewer_compare_load(&a->v, o.reference, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_script_free(&a->script);
        dm_viewer_free(&a->v);
        free(a);
        return DM_EXIT_LOAD;
    }

    /* window + renderer */
    int rc = DM_EXIT_OK;
    int w = a->v.opt.width > 0 ? a->v.opt.width : a->v.scene.width,
        h = a->v.opt.height > 0 ? a->v.opt.height : a->v.scene.height;
    a->v.opt.width = w, a->v.opt.height = h;
    char title[1200];
    snprintf(title, sizeof title, "dermis-view — %s", o.v.pack ? o.v.pack : "synthetic");
    if (dm_glfw_create(w, h, title, true, &a->window, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_script_free(&a->script);
        dm_viewer_free(&a->v);
        free(a);
        return DM_EXIT_PROCESS;
    }
    glfwSetWindowUserPointer(a->window, a);
    glfwSetKeyCallback(a->window, on_key);
    glfwSetMouseButtonCallback(a->window, on_button);
    glfwSetCursorPosCallback(a->window, on_cursor);
    glfwSetScrollCallback(a->window, on_scroll);
    if (!dm_ui_init(a->window)) {
        fprintf(stderr, "error: the UI (Dear ImGui) cannot start on this context\n");
        rc = DM_EXIT_PROCESS;
        goto done_window;
    }
    if (dm_viewer_start(&a->v, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        rc = DM_EXIT_PROCESS;
        goto done_ui;
    }
    if (o.v.verbose) fprintf(stderr, "renderer: %s\n", dm_renderer_gl_name(a->v.r));

    /* event loop: the picture renders only when something changed */
    double t0 = dm_now_ms(), last = t0;
    while (!glfwWindowShouldClose(a->window) && !a->v.quit) {
        double now = dm_now_ms();
        dm_viewer_watch(&a->v, now);
        if (a->scripted) run_script(a, (now - t0) / 1000.0);
        if (a->v.quit) break;
        dm_viewer_update(&a->v, (now - last) / 1000.0);
        last = now;
        double u0 = dm_now_ms();
        int fw, fh;
        glfwGetFramebufferSize(a->window, &fw, &fh);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glViewport(0, 0, fw, fh);
        glClearColor(0.08f, 0.08f, 0.09f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        dm_ui_frame(&a->v);
        dm_ui_render();
        if (a->window_shot[0] && a->window_shot_wait-- <= 0) capture_window(a);
        for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
            a->v.gl_errors++;
            dm_viewer_set_status(&a->v, true, "GL error 0x%04x in the UI frame", (unsigned)e);
        }
        glfwSwapBuffers(a->window);
        a->v.ui_ms = dm_now_ms() - u0;
        bool busy = a->scripted || a->v.dirty || a->v.light_rotating || a->window_shot[0];
        if (busy) glfwPollEvents();
        else glfwWaitEventsTimeout(0.5); /* idle: wake for input, --watch, or a redraw */
    }
    if (a->scripted && !o.v.quiet)
        printf("script %s: %d events, %d frames, %d failed, %d GL errors\n", o.script, a->script.next,
               a->v.frames, a->v.failures, a->v.gl_errors);
    if (a->scripted && !o.v.quiet && a->v.skin.ms_count)
        printf("skin: %d changes, refit + hand-over median %.2f ms\n", a->v.skin.ms_count,
               dm_viewer_skin_median_ms(&a->v));
    if (a->v.gl_errors || (a->scripted && a->v.failures > a->save_failures)) rc = DM_EXIT_PROCESS;
    else if (a->scripted && a->save_failures) rc = DM_EXIT_SAVE;
    dm_viewer_free(&a->v);
done_ui:
    dm_ui_shutdown();
done_window:
    dm_glfw_destroy(a->window);
    dm_script_free(&a->script);
    free(a);
    return rc;
}
