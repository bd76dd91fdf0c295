#include "dm_viewer_script.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_cli.h"
#include "core/dm_input.h"
#include "core/dm_output.h"

typedef struct command_spec {
    const char *name;
    int min_args, max_args;
    int numeric_from; /* args from this index on are numbers (−1: none) */
} command_spec;

static const command_spec specs[] = {
    {"key", 1, 1, -1},        {"drag", 4, 5, 0},       {"scroll", 1, 1, 0},     {"toggle", 1, 2, -1},
    {"view", 1, 1, -1},       {"set", 2, 4, 1},        {"screenshot", 1, 1, -1}, {"window-shot", 1, 1, -1},
    {"quit", 0, 0, -1},       {"env", 1, 1, 0},        {"compare", 1, 1, -1},   {"technique", 1, 1, -1},
};

/* A finite number (strtod alone also takes "nan" and "inf"). */
static bool number(const char *t)
{
    char *end;
    double d = strtod(t, &end);
    return end != t && *end == 0 && isfinite(d);
}

dm_result dm_script_read(const char *path, dm_script *s, dm_error *err)
{
    memset(s, 0, sizeof *s);
    char *text = NULL;
    size_t size = 0;
    dm_result rc = dm_input_read(path, DM_INPUT_SCRIPT, &text, &size, err);
    if (rc != DM_OK) return rc;
    if (memchr(text, 0, size)) rc = dm_fail(err, DM_ERR_FORMAT, "%s: holds a NUL byte, expected text", path);
    if (rc == DM_OK) rc = dm_script_parse(text, path, s, err);
    free(text);
    return rc;
}

dm_result dm_script_parse(char *text, const char *path, dm_script *s, dm_error *err)
{
    memset(s, 0, sizeof *s);
    s->path = path;
    dm_result rc = DM_OK;
    int cap = 0, line = 0;
    double last = 0;
    for (char *p = text; p && *p;) {
        char *ln = p, *nl = strchr(p, '\n');
        if (nl) *nl = 0;
        p = nl ? nl + 1 : NULL;
        ++line;
        char *hash = strchr(ln, '#');
        if (hash) *hash = 0;
        dm_script_event e = {.line = line};
        char *tok_save = NULL, *tok = strtok_r(ln, " \t\r", &tok_save);
        if (!tok) continue;
        char *end;
        e.time_s = strtod(tok, &end);
        if (end == tok || *end || !(e.time_s >= 0) || e.time_s > 1e6) {
            rc = dm_fail(err, DM_ERR_FORMAT, "%s:%d: error: '%s' is not a time in seconds [0, 1e6]", path, line, tok);
            break;
        }
        if (e.time_s < last) {
            rc = dm_fail(err, DM_ERR_FORMAT, "%s:%d: error: time %g is before the previous event's %g", path, line,
                         e.time_s, last);
            break;
        }
        last = e.time_s;
        tok = strtok_r(NULL, " \t\r", &tok_save);
        const command_spec *spec = NULL;
        for (size_t i = 0; tok && i < sizeof specs / sizeof specs[0]; ++i)
            if (!strcmp(tok, specs[i].name)) spec = &specs[i];
        if (!spec) {
            rc = dm_fail(err, DM_ERR_FORMAT,
                         "%s:%d: error: '%s' is not a command (key, drag, scroll, toggle, view, set, env, "
                         "compare, technique, screenshot, window-shot, quit)",
                         path, line, tok ? tok : "");
            break;
        }
        snprintf(e.command, sizeof e.command, "%s", spec->name);
        while ((tok = strtok_r(NULL, " \t\r", &tok_save))) {
            if (e.arg_count == DM_SCRIPT_MAX_ARGS) break;
            snprintf(e.args[e.arg_count++], DM_SCRIPT_ARG_SIZE, "%s", tok);
        }
        if (e.arg_count < spec->min_args || e.arg_count > spec->max_args || tok) {
            rc = dm_fail(err, DM_ERR_FORMAT, "%s:%d: error: %s takes %d to %d arguments, got %d%s", path, line,
                         spec->name, spec->min_args, spec->max_args, e.arg_count, tok ? " or more" : "");
            break;
        }
        int last_numeric = e.arg_count;
        if (!strcmp(spec->name, "drag") && e.arg_count == 5) last_numeric = 4; /* the button name */
        for (int a = spec->numeric_from; a >= 0 && a < last_numeric; ++a)
            if (!number(e.args[a])) {
                rc = dm_fail(err, DM_ERR_FORMAT, "%s:%d: error: %s: '%s' is not a number", path, line, spec->name,
                             e.args[a]);
                break;
            }
        if (rc != DM_OK) break;
        if (!strcmp(spec->name, "drag") && e.arg_count == 5 && strcmp(e.args[4], "left") &&
            strcmp(e.args[4], "right") && strcmp(e.args[4], "middle") && strcmp(e.args[4], "light")) {
            rc = dm_fail(err, DM_ERR_FORMAT, "%s:%d: error: drag: '%s' is not left, right, middle or light", path,
                         line, e.args[4]);
            break;
        }
        /* an int-valued setting is checked here, as an integer in its range: (int)3e9 is undefined */
        double irr = !strcmp(spec->name, "set") && !strcmp(e.args[0], "irradiance") ? strtod(e.args[1], NULL) : 512;
        if (!(irr >= 8 && irr <= 8192 && irr == floor(irr))) {
            rc = dm_fail(err, DM_ERR_FORMAT, "%s:%d: error: set irradiance: '%s' is not an integer in [8, 8192]", path,
                         line, e.args[1]);
            break;
        }
        if ((!strcmp(spec->name, "screenshot") || !strcmp(spec->name, "window-shot")) &&
            dm_output_extension(e.args[0], (const char *const[]){".png", NULL}) < 0) {
            rc = dm_fail(err, DM_ERR_FORMAT, "%s:%d: error: %s %s: expected a name ending in .png (any case): "
                         "screenshots are PNG", path, line, spec->name, e.args[0]);
            break;
        }
        if (s->count == cap) {
            cap = cap ? 2 * cap : 32;
            dm_script_event *n = realloc(s->events, (size_t)cap * sizeof *n);
            if (!n) {
                rc = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
                break;
            }
            s->events = n;
        }
        s->events[s->count++] = e;
    }
    if (rc != DM_OK) dm_script_free(s);
    return rc;
}

int dm_script_check_outputs(const dm_script *s, const char *const *inputs, int input_count)
{
    for (int k = 0; k < s->count; ++k) {
        const dm_script_event *e = &s->events[k];
        if (strcmp(e->command, "screenshot") && strcmp(e->command, "window-shot")) continue;
        dm_error err = {0};
        dm_result r = dm_output_check(e->command, e->args[0], (const char *const[]){".png", NULL}, inputs,
                                      input_count, NULL, &err);
        if (r != DM_OK) {
            fprintf(stderr, "error: %s:%d: %s\n", s->path, e->line, err.detail);
            return r == DM_ERR_FILE_WRITE ? DM_EXIT_SAVE : DM_EXIT_USAGE;
        }
    }
    return 0;
}

void dm_script_free(dm_script *s)
{
    free(s->events);
    s->events = NULL;
    s->count = s->next = 0;
}
