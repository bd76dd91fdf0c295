/* dm_scene.c — the scene reader (core/dm_scene.h): the strict JSON reader (core/dm_jread.h)
 * over each section, its file paths resolved by dm_scene_paths.c. Defaults and names:
 * dm_scene_defaults.c; the writer: dm_scene_write.c. */
#include "core/dm_scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cJSON.h>

#include "core/dm_file.h"
#include "core/dm_input.h"
#include "core/dm_format_policy.h"
#include "core/dm_jread.h"
#include "core/dm_scene_paths.h"

/* --- reading: core/dm_jread.h; paths resolved by dm_scene_paths.c ------------------- */

typedef struct ctx {
    dm_jread j; /* where = the scene file */
    dm_scene_paths paths;
} ctx;

static bool get_path(ctx *c, const cJSON *obj, const char *jpath, const char *key, bool allow_empty,
                     char out[DM_SCENE_PATH_SIZE])
{
    const cJSON *v = dm_jread_get(obj, key);
    if (!v) return true;
    char p[DM_JPATH_SIZE];
    dm_jread_path(p, jpath, key);
    if (!cJSON_IsString(v)) return dm_jread_fail(&c->j, DM_ERR_FORMAT, p, v, "a file path string");
    if (!allow_empty && !*v->valuestring) return dm_jread_fail(&c->j, DM_ERR_RANGE, p, v, "a non-empty file path");
    return dm_scene_resolve_path(&c->paths, &c->j, p, v->valuestring, out);
}

/* --- sections ---------------------------------------------------------------------- */

static bool parse_mesh(ctx *c, const cJSON *root, dm_scene *s)
{
    static const char *const keys[] = {"path", "mm_per_unit", "name", NULL};
    bool ok;
    const cJSON *m = dm_jread_object(&c->j, root, "$", "mesh", true, &ok);
    if (!ok || !dm_jread_keys(&c->j, m, "$.mesh", keys)) return false;
    if (!dm_jread_get(m, "path")) {
        c->j.r = dm_fail(c->j.err, DM_ERR_FORMAT, "%s: $.mesh.path: missing, expected the mesh file's path", c->j.where);
        return false;
    }
    const cJSON *name = dm_jread_get(m, "name");
    if (name && (!cJSON_IsString(name) || strlen(name->valuestring) >= DM_SCENE_NAME_SIZE))
        return dm_jread_fail(&c->j, cJSON_IsString(name) ? DM_ERR_RANGE : DM_ERR_FORMAT, "$.mesh.name", name,
                          "a glTF mesh name string under 128 bytes");
    if (name) snprintf(s->mesh_name, sizeof s->mesh_name, "%s", name->valuestring);
    return get_path(c, m, "$.mesh", "path", false, s->mesh) &&
           dm_jread_double_opt(&c->j, m, "$.mesh", "mm_per_unit", 1e-6, 1e6, &s->mm_per_unit);
}

/* "albedo_from": "map" or "skin" (whether a skin profile backs it is checked once the effects
 * are read: check_albedo_from). */
static bool parse_albedo_from(ctx *c, const cJSON *m, dm_scene *s)
{
    const cJSON *v = dm_jread_get(m, "albedo_from");
    if (!v) return true;
    const char *want = "\"map\" or \"skin\"";
    if (!cJSON_IsString(v)) return dm_jread_fail(&c->j, DM_ERR_FORMAT, "$.material.albedo_from", v, want);
    if (strcmp(v->valuestring, "map") && strcmp(v->valuestring, "skin"))
        return dm_jread_fail(&c->j, DM_ERR_RANGE, "$.material.albedo_from", v, want);
    s->albedo_from = strcmp(v->valuestring, "skin") ? DM_ALBEDO_FROM_MAP : DM_ALBEDO_FROM_SKIN;
    return true;
}

/* The colour from the skin needs a skin: the profile must be {"skin": {…}}. */
static bool check_albedo_from(ctx *c, const dm_scene *s)
{
    if (s->albedo_from != DM_ALBEDO_FROM_SKIN || s->skin.given) return true;
    c->j.r = dm_fail(c->j.err, DM_ERR_MISMATCH,
                     "%s: $.material.albedo_from: \"skin\" takes the colour from a physical skin, but "
                     "$.effects.subsurface.profile is %s, expected {\"skin\": {...}} there or albedo_from \"map\"",
                     c->j.where, s->profile_source[0] && strcmp(s->profile_source, "inline") ? s->profile_source
                                                                                           : "a Gaussian profile");
    return false;
}

static bool parse_material(ctx *c, const cJSON *root, dm_scene *s)
{
    static const char *const keys[] = {"albedo",    "normal_map", "specular_map", "roughness_map",
                                       "roughness", "rho_s",      "albedo_from",  NULL};
    bool ok;
    const cJSON *m = dm_jread_object(&c->j, root, "$", "material", false, &ok);
    if (!ok) return false;
    if (!m) return true;
    return dm_jread_keys(&c->j, m, "$.material", keys) && get_path(c, m, "$.material", "albedo", true, s->albedo) &&
           get_path(c, m, "$.material", "normal_map", true, s->normal_map) &&
           get_path(c, m, "$.material", "specular_map", true, s->specular_map) &&
           get_path(c, m, "$.material", "roughness_map", true, s->roughness_map) &&
           dm_jread_float_opt(&c->j, m, "$.material", "roughness", 0.0, 1.0, &s->roughness) &&
           dm_jread_float_opt(&c->j, m, "$.material", "rho_s", 0.0, 1.0, &s->rho_s) && parse_albedo_from(c, m, s);
}

static bool parse_light(ctx *c, const cJSON *l, const char *jpath, dm_light *out)
{
    static const char *const dir_keys[] = {"type", "direction", "color", "intensity", "casts_shadow", NULL};
    static const char *const point_keys[] = {"type", "position", "color", "intensity", "casts_shadow", NULL};
    if (!cJSON_IsObject(l)) return dm_jread_fail(&c->j, DM_ERR_FORMAT, jpath, l, "an object");
    const cJSON *t = dm_jread_get(l, "type");
    char p[DM_JPATH_SIZE];
    dm_jread_path(p, jpath, "type");
    if (!t) {
        c->j.r = dm_fail(c->j.err, DM_ERR_FORMAT, "%s: %s: missing, expected \"directional\" or \"point\"", c->j.where, p);
        return false;
    }
    if (!cJSON_IsString(t) ||
        (strcmp(t->valuestring, "directional") != 0 && strcmp(t->valuestring, "point") != 0))
        return dm_jread_fail(&c->j, DM_ERR_FORMAT, p, t, "\"directional\" or \"point\"");
    memset(out, 0, sizeof *out);
    out->type = strcmp(t->valuestring, "point") == 0 ? DM_LIGHT_POINT : DM_LIGHT_DIRECTIONAL;
    out->color[0] = out->color[1] = out->color[2] = 1.0f;
    out->intensity = 1.0f;
    out->casts_shadow = true;
    const char *need = out->type == DM_LIGHT_POINT ? "position" : "direction";
    if (!dm_jread_keys(&c->j, l, jpath, out->type == DM_LIGHT_POINT ? point_keys : dir_keys)) return false;
    if (!dm_jread_get(l, need)) {
        dm_jread_path(p, jpath, need);
        c->j.r = dm_fail(c->j.err, DM_ERR_FORMAT, "%s: %s: missing, expected an array of 3 numbers (a %s light needs it)",
                       c->j.where, p, t->valuestring);
        return false;
    }
    if (out->type == DM_LIGHT_POINT) {
        if (!dm_jread_vec3_opt(&c->j, l, jpath, "position", -1e6, 1e6, false, out->position)) return false;
    } else {
        if (!dm_jread_vec3_opt(&c->j, l, jpath, "direction", -1e6, 1e6, true, out->direction)) return false;
        double n = sqrt((double)out->direction[0] * out->direction[0] + (double)out->direction[1] * out->direction[1] +
                        (double)out->direction[2] * out->direction[2]);
        for (int k = 0; k < 3; ++k) out->direction[k] = (float)(out->direction[k] / n);
    }
    return dm_jread_vec3_opt(&c->j, l, jpath, "color", 0.0, 1e6, false, out->color) &&
           dm_jread_float_opt(&c->j, l, jpath, "intensity", 0.0, 1e6, &out->intensity) &&
           dm_jread_bool_opt(&c->j, l, jpath, "casts_shadow", &out->casts_shadow);
}

/* The optional array `key` of obj (at jpath) of at most max items: *out NULL when absent;
 * false, reported, when it is not such an array. noun names the items in the expectation
 * ("lights"), unit in the count ("lights", "maps"). */
static bool bounded_array(ctx *c, const cJSON *obj, const char *key, const char *jpath, int max, const char *noun,
                          const char *unit, const cJSON **out, int *n)
{
    *out = dm_jread_get(obj, key);
    *n = 0;
    if (!*out) return true;
    char want[96];
    snprintf(want, sizeof want, "an array of at most %d %s", max, noun);
    if (!cJSON_IsArray(*out)) return dm_jread_fail(&c->j, DM_ERR_FORMAT, jpath, *out, want);
    *n = cJSON_GetArraySize(*out);
    if (*n > max) {
        c->j.r = dm_fail(c->j.err, DM_ERR_RANGE, "%s: %s: %d %s, expected at most %d", c->j.where, jpath, *n, unit, max);
        return false;
    }
    return true;
}

static bool parse_lights(ctx *c, const cJSON *root, dm_scene *s)
{
    const cJSON *ls;
    int n;
    if (!bounded_array(c, root, "lights", "$.lights", DM_SCENE_MAX_LIGHTS, "lights", "lights", &ls, &n)) return false;
    if (!ls) return true;
    s->light_count = 0;
    int k = 0;
    for (const cJSON *l = ls->child; l; l = l->next, ++k) {
        char p[DM_JPATH_SIZE];
        snprintf(p, sizeof p, "$.lights[%d]", k);
        if (!parse_light(c, l, p, &s->lights[k])) return false;
        s->light_count = k + 1;
    }
    return true;
}

/* "alternatives": an array of at most DM_SCENE_MAX_ENV_ALTERNATIVES non-empty paths. */
static bool parse_env_alternatives(ctx *c, const cJSON *e, dm_scene *s)
{
    const cJSON *v;
    int n;
    if (!bounded_array(c, e, "alternatives", "$.environment.alternatives", DM_SCENE_MAX_ENV_ALTERNATIVES,
                       "environment map paths", "maps", &v, &n))
        return false;
    if (!v) return true;
    if (n > 0 && !*s->environment) {
        c->j.r = dm_fail(c->j.err, DM_ERR_MISMATCH,
                       "%s: $.environment.alternatives: %d maps, but $.environment.path is missing, expected the "
                       "main map first",
                       c->j.where, n);
        return false;
    }
    s->env_alternative_count = 0;
    int k = 0;
    for (const cJSON *a = v->child; a; a = a->next, ++k) {
        char p[DM_JPATH_SIZE];
        snprintf(p, sizeof p, "$.environment.alternatives[%d]", k);
        if (!cJSON_IsString(a)) return dm_jread_fail(&c->j, DM_ERR_FORMAT, p, a, "a file path string");
        if (!*a->valuestring) return dm_jread_fail(&c->j, DM_ERR_RANGE, p, a, "a non-empty file path");
        if (!dm_scene_resolve_path(&c->paths, &c->j, p, a->valuestring, s->env_alternatives[k])) return false;
        s->env_alternative_count = k + 1;
    }
    return true;
}

static bool parse_environment(ctx *c, const cJSON *root, dm_scene *s)
{
    static const char *const keys[] = {"path", "intensity", "rotation_deg", "background", "alternatives", NULL};
    bool ok;
    const cJSON *e = dm_jread_object(&c->j, root, "$", "environment", false, &ok);
    if (!ok) return false;
    if (!e) return true;
    return dm_jread_keys(&c->j, e, "$.environment", keys) && get_path(c, e, "$.environment", "path", true, s->environment) &&
           dm_jread_float_opt(&c->j, e, "$.environment", "intensity", 0.0, 1e6, &s->env_intensity) &&
           dm_jread_float_opt(&c->j, e, "$.environment", "rotation_deg", -360.0, 360.0, &s->env_rotation_deg) &&
           dm_jread_bool_opt(&c->j, e, "$.environment", "background", &s->env_background) && parse_env_alternatives(c, e, s);
}

/* {"skin": {"preset": NAME, KEY: number, …}}: names and types checked, numbers stored (the
 * packer checks the ranges and fits the profile: the model is offline). */
static bool parse_skin(ctx *c, const cJSON *v, const char *jpath, dm_scene *s)
{
    char p[DM_JPATH_SIZE];
    dm_jread_path(p, jpath, "skin");
    static const char *const top[] = {"skin", NULL};
    if (!dm_jread_keys(&c->j, v, jpath, top)) return false;
    const cJSON *skin = dm_jread_get(v, "skin");
    if (!cJSON_IsObject(skin)) return dm_jread_fail(&c->j, DM_ERR_FORMAT, p, skin, "an object of skin parameters");
    dm_scene_skin *k = &s->skin;
    memset(k, 0, sizeof *k);
    const cJSON *e;
    cJSON_ArrayForEach(e, skin)
    {
        char ep[DM_JPATH_SIZE];
        dm_jread_path(ep, p, e->string);
        if (!strcmp(e->string, "preset")) {
            if (!cJSON_IsString(e) || !*e->valuestring || strlen(e->valuestring) >= sizeof k->preset)
                return dm_jread_fail(&c->j, DM_ERR_FORMAT, ep, e, "a preset name (dermis-fit-profile --list-presets)");
            snprintf(k->preset, sizeof k->preset, "%s", e->valuestring);
            continue;
        }
        int i = dm_skin_key_index(e->string, strlen(e->string));
        if (i < 0) {
            char want[160];
            snprintf(want, sizeof want, "a key among preset, %s", dm_skin_keys_text());
            return dm_jread_fail(&c->j, DM_ERR_FORMAT, ep, e, want);
        }
        if (!cJSON_IsNumber(e)) return dm_jread_fail(&c->j, DM_ERR_FORMAT, ep, e, "a number");
        for (int j = 0; j < k->key_count; ++j)
            if (k->key[j] == i) return dm_jread_fail(&c->j, DM_ERR_FORMAT, ep, e, "each key once");
        k->key[k->key_count] = i;
        k->value[k->key_count++] = e->valuedouble;
    }
    for (int i = 0; !k->preset[0] && i < DM_SKIN_KEY_REQUIRED_COUNT; ++i) {
        bool seen = false;
        for (int j = 0; j < k->key_count; ++j) seen = seen || k->key[j] == i;
        if (!seen) {
            char want[160];
            snprintf(want, sizeof want, "\"%s\" (melanin, eumelanin and blood are required without a preset)",
                     dm_skin_keys[i]);
            return dm_jread_fail(&c->j, DM_ERR_FORMAT, p, skin, want);
        }
    }
    k->given = true;
    dm_profile_gems3_skin(&s->profile); /* the stand-in until the packer fits the skin's */
    snprintf(s->profile_source, sizeof s->profile_source, "skin");
    return true;
}

static bool parse_profile(ctx *c, const cJSON *v, const char *jpath, dm_scene *s)
{
    if (cJSON_IsObject(v) && dm_jread_get(v, "skin")) return parse_skin(c, v, jpath, s);
    if (cJSON_IsObject(v)) { /* inline, in the dm_profile.h JSON form (what dm_scene_to_json writes) */
        char what[DM_SCENE_PATH_SIZE + DM_JPATH_SIZE];
        snprintf(what, sizeof what, "%s: %s", c->j.where, jpath);
        dm_result r = dm_profile_from_cjson(v, what, &s->profile, c->j.err);
        if (r != DM_OK) {
            c->j.r = r;
            return false;
        }
        snprintf(s->profile_source, sizeof s->profile_source, "inline");
        return true;
    }
    if (!cJSON_IsString(v) || !*v->valuestring)
        return dm_jread_fail(&c->j, DM_ERR_FORMAT, jpath, v, "\"gems3-skin\", a profile JSON path or a profile object");
    if (strcmp(v->valuestring, "gems3-skin") == 0) {
        dm_profile_gems3_skin(&s->profile);
        snprintf(s->profile_source, sizeof s->profile_source, "gems3-skin");
        return true;
    }
    if (!dm_scene_resolve_path(&c->paths, &c->j, jpath, v->valuestring, s->profile_source)) return false;
    struct stat st;
    if (stat(s->profile_source, &st) != 0 || !S_ISREG(st.st_mode)) {
        char want[DM_SCENE_PATH_SIZE + 64];
        snprintf(want, sizeof want, "\"gems3-skin\" or an existing profile file (looked for %s)", s->profile_source);
        return dm_jread_fail(&c->j, DM_ERR_FILE_OPEN, jpath, v, want);
    }
    dm_result r = dm_profile_read(s->profile_source, &s->profile, c->j.err);
    if (r != DM_OK) {
        char inner[sizeof c->j.err->detail];
        snprintf(inner, sizeof inner, "%s", c->j.err ? c->j.err->detail : "");
        c->j.r = dm_fail(c->j.err, r, "%s: %s: %s", c->j.where, jpath, inner);
        return false;
    }
    return true;
}

/* An effect is `true`, `false`, or an object whose "enabled" defaults to true. */
static bool parse_effect(ctx *c, const cJSON *effects, dm_effect e, const char *const *extra_keys, dm_scene *s,
                         const cJSON **params)
{
    const char *name = dm_effect_name(e);
    const cJSON *v = dm_jread_get(effects, name);
    char p[DM_JPATH_SIZE];
    dm_jread_path(p, "$.effects", name);
    *params = NULL;
    if (!v) return true;
    if (cJSON_IsBool(v)) {
        s->effects[e] = cJSON_IsTrue(v);
        return true;
    }
    if (!cJSON_IsObject(v)) return dm_jread_fail(&c->j, DM_ERR_FORMAT, p, v, "true, false or an object");
    const char *keys[12] = {"enabled"};
    int n = 1;
    for (const char *const *k = extra_keys; k && *k && n < 11; ++k) keys[n++] = *k;
    keys[n] = NULL;
    if (!dm_jread_keys(&c->j, v, p, keys)) return false;
    bool on = true;
    if (!dm_jread_bool_opt(&c->j, v, p, "enabled", &on)) return false;
    s->effects[e] = on;
    *params = v;
    return true;
}

/* effects.subsurface.technique (a name from technique_names, available) and screen_taps (one
 * of DM_SCENE_SCREEN_TAPS_LIST). */
static bool parse_technique(ctx *c, const cJSON *pm, dm_scene *s)
{
    const cJSON *v = dm_jread_get(pm, "technique");
    if (v) {
        const char *p = "$.effects.subsurface.technique";
        const char *want = "\"texture-space\", \"screen-space\" or \"pre-integrated\"";
        if (!cJSON_IsString(v)) return dm_jread_fail(&c->j, DM_ERR_FORMAT, p, v, want);
        int t = -1;
        for (int k = 0; k < DM_SSS_TECHNIQUE_COUNT; ++k)
            if (strcmp(v->valuestring, dm_sss_technique_name((dm_sss_technique)k)) == 0) t = k;
        if (t < 0) return dm_jread_fail(&c->j, DM_ERR_RANGE, p, v, want);
        if (!dm_sss_technique_available((dm_sss_technique)t)) {
            c->j.r = dm_fail(c->j.err, DM_ERR_UNSUPPORTED, "%s: %s: \"%s\" is a known technique but not implemented yet, expected %s",
                           c->j.where, p, v->valuestring, "\"texture-space\" or \"screen-space\"");
            return false;
        }
        s->sss_technique = (dm_sss_technique)t;
    }
    v = dm_jread_get(pm, "screen_taps");
    if (v) {
        static const int list[] = DM_SCENE_SCREEN_TAPS_LIST;
        const char *p = "$.effects.subsurface.screen_taps", *want = "one of 11, 17, 25";
        if (!cJSON_IsNumber(v)) return dm_jread_fail(&c->j, DM_ERR_FORMAT, p, v, want);
        bool ok = false;
        for (size_t k = 0; k < sizeof list / sizeof list[0]; ++k)
            if (v->valuedouble == list[k]) ok = true;
        if (!ok) return dm_jread_fail(&c->j, DM_ERR_RANGE, p, v, want);
        s->screen_taps = (int)v->valuedouble;
    }
    return true;
}

static bool parse_effects(ctx *c, const cJSON *root, dm_scene *s)
{
    static const char *const sss_keys[] = {"profile", "taps", "irradiance_size", "mix", "technique", "screen_taps", NULL};
    static const char *const translucency_keys[] = {"intensity", NULL};
    static const char *const glow_keys[] = {"threshold", "intensity", NULL};
    static const char *const tone_keys[] = {"exposure", NULL};
    bool ok;
    const cJSON *fx = dm_jread_object(&c->j, root, "$", "effects", true, &ok); /* a scene names its effects */
    if (!ok) return false;
    const char *keys[DM_EFFECT_COUNT + 1];
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) keys[e] = dm_effect_name((dm_effect)e);
    keys[DM_EFFECT_COUNT] = NULL;
    if (!dm_jread_keys(&c->j, fx, "$.effects", keys)) return false;
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) s->effects[e] = false; /* listed effects only */
    const cJSON *pm;
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) {
        const char *const *extra = e == DM_EFFECT_SUBSURFACE ? sss_keys
                                   : e == DM_EFFECT_GLOW     ? glow_keys
                                   : e == DM_EFFECT_TONEMAP  ? tone_keys
                                   : e == DM_EFFECT_TRANSLUCENCY ? translucency_keys
                                                             : NULL;
        if (!parse_effect(c, fx, (dm_effect)e, extra, s, &pm)) return false;
        if (!pm) continue;
        if (e == DM_EFFECT_SUBSURFACE) {
            const char *p = "$.effects.subsurface";
            const cJSON *prof = dm_jread_get(pm, "profile");
            if (prof && !parse_profile(c, prof, "$.effects.subsurface.profile", s)) return false;
            if (!dm_jread_int_opt(&c->j, pm, p, "taps", 3, DM_BLUR_TAPS_MAX, true, &s->blur_taps) ||
                !dm_jread_int_opt(&c->j, pm, p, "irradiance_size", 64, 8192, false, &s->irradiance_size) ||
                !dm_jread_float_opt(&c->j, pm, p, "mix", 0.0, 1.0, &s->mix) || !parse_technique(c, pm, s))
                return false;
        } else if (e == DM_EFFECT_GLOW) {
            if (!dm_jread_float_opt(&c->j, pm, "$.effects.glow", "threshold", 0.0, 1e6, &s->glow_threshold) ||
                !dm_jread_float_opt(&c->j, pm, "$.effects.glow", "intensity", 0.0, 100.0, &s->glow_intensity))
                return false;
        } else if (e == DM_EFFECT_TONEMAP) {
            if (!dm_jread_float_opt(&c->j, pm, "$.effects.tonemap", "exposure", -20.0, 20.0, &s->exposure)) return false;
        } else if (e == DM_EFFECT_TRANSLUCENCY) {
            if (!dm_jread_float_opt(&c->j, pm, "$.effects.translucency", "intensity", 0.0, 100.0, &s->translucency_intensity))
                return false;
        }
    }
    return true;
}

static bool parse_camera(ctx *c, const cJSON *root, dm_scene *s)
{
    static const char *const keys[] = {"eye", "target", "up", "fov_y_deg", NULL};
    bool ok;
    const cJSON *cam = dm_jread_object(&c->j, root, "$", "camera", false, &ok);
    if (!ok) return false;
    if (!cam) return true;
    if (!dm_jread_keys(&c->j, cam, "$.camera", keys) || !dm_jread_vec3_opt(&c->j, cam, "$.camera", "eye", -1e6, 1e6, false, s->camera_eye) ||
        !dm_jread_vec3_opt(&c->j, cam, "$.camera", "target", -1e6, 1e6, false, s->camera_target) ||
        !dm_jread_vec3_opt(&c->j, cam, "$.camera", "up", -1e6, 1e6, true, s->camera_up) ||
        !dm_jread_float_opt(&c->j, cam, "$.camera", "fov_y_deg", 1.0, 179.0, &s->fov_y_deg))
        return false;
    double d[3], len2 = 0.0, cr[3], cr2 = 0.0, up2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        d[k] = (double)s->camera_target[k] - s->camera_eye[k];
        len2 += d[k] * d[k];
        up2 += (double)s->camera_up[k] * s->camera_up[k];
    }
    if (!(len2 > 1e-12)) {
        c->j.r = dm_fail(c->j.err, DM_ERR_RANGE, "%s: $.camera.eye: equals $.camera.target, expected a distinct point",
                       c->j.where);
        return false;
    }
    const float *u = s->camera_up;
    cr[0] = d[1] * u[2] - d[2] * u[1];
    cr[1] = d[2] * u[0] - d[0] * u[2];
    cr[2] = d[0] * u[1] - d[1] * u[0];
    for (int k = 0; k < 3; ++k) cr2 += cr[k] * cr[k];
    if (!(cr2 > 1e-8 * len2 * up2)) {
        c->j.r = dm_fail(c->j.err, DM_ERR_RANGE,
                       "%s: $.camera.up: [%g, %g, %g] is parallel to the view direction, expected a vector across it",
                       c->j.where, u[0], u[1], u[2]);
        return false;
    }
    return true;
}

static bool parse_output(ctx *c, const cJSON *root, dm_scene *s)
{
    static const char *const keys[] = {"width", "height", NULL};
    bool ok;
    const cJSON *o = dm_jread_object(&c->j, root, "$", "output", false, &ok);
    if (!ok) return false;
    if (!o) return true;
    return dm_jread_keys(&c->j, o, "$.output", keys) && dm_jread_int_opt(&c->j, o, "$.output", "width", 1, 16384, false, &s->width) &&
           dm_jread_int_opt(&c->j, o, "$.output", "height", 1, 16384, false, &s->height);
}

static bool parse_header(ctx *c, const cJSON *root)
{
    const cJSON *f = dm_jread_get(root, "format"), *v = dm_jread_get(root, "version");
    if (f && (!cJSON_IsString(f) || strcmp(f->valuestring, "dermis-scene") != 0))
        return dm_jread_fail(&c->j, DM_ERR_FORMAT, "$.format", f, "\"dermis-scene\"");
    if (v && (!cJSON_IsNumber(v) || v->valuedouble != DM_SCENE_VERSION)) { /* docs/dermis-scene.5.md's policy */
        bool integer = cJSON_IsNumber(v) && v->valuedouble == floor(v->valuedouble) && fabs(v->valuedouble) < 1e18;
        char want[160];
        snprintf(want, sizeof want, "%d (%s)", DM_SCENE_VERSION,
                 integer ? dm_format_advice(DM_FORMAT_SCENE, dm_format_judge((int64_t)v->valuedouble, DM_SCENE_VERSION))
                         : "the scene version this dermis reads");
        return dm_jread_fail(&c->j, DM_ERR_UNSUPPORTED, "$.version", v, want);
    }
    return true;
}

/* Line and column of byte `at` in text, for JSON syntax errors. */
static void line_col(const char *text, const char *at, int *line, int *col)
{
    *line = 1;
    *col = 1;
    for (const char *p = text; p < at && *p; ++p) {
        if (*p == '\n') {
            ++*line;
            *col = 1;
        } else {
            ++*col;
        }
    }
}

/* The scene from a parsed root: every key read, ranges and cross-checks. */
static dm_result scene_from_root(const cJSON *root, const char *path, bool search, const char *const *asset_dirs,
                                 int asset_dir_count, dm_scene *s, dm_error *err)
{
    static const char *const keys[] = {"format", "version", "mesh",    "material", "lights",
                                       "environment", "effects", "camera", "output", NULL};
    dm_scene_defaults(s);
    ctx c = {.j = {.where = path ? path : "(scene)", .err = err, .r = DM_OK},
             .paths = {.search = search, .asset_dirs = asset_dirs, .asset_dir_count = asset_dir_count}};
    snprintf(s->path, sizeof s->path, "%s", c.j.where);
    dm_dirname(c.j.where, c.paths.dir, sizeof c.paths.dir);
    bool ok = true;
    if (!cJSON_IsObject(root)) ok = dm_jread_fail(&c.j, DM_ERR_FORMAT, "$", root, "a JSON object");
    ok = ok && dm_jread_keys(&c.j, root, "$", keys) && parse_header(&c, root) && parse_mesh(&c, root, s) &&
         parse_material(&c, root, s) && parse_lights(&c, root, s) && parse_environment(&c, root, s) &&
         parse_effects(&c, root, s) && check_albedo_from(&c, s) && parse_camera(&c, root, s) &&
         parse_output(&c, root, s);
    if (ok && s->effects[DM_EFFECT_ENVIRONMENT_LIGHTING] && !*s->environment) {
        c.j.r = dm_fail(err, DM_ERR_MISMATCH,
                      "%s: $.effects.environment_lighting: on, but $.environment.path is missing, expected an "
                      "environment map or the effect turned off",
                      c.j.where);
        ok = false;
    }
    return ok ? DM_OK : c.j.r;
}

static dm_result parse_scene(const char *json, const char *path, bool search, const char *const *asset_dirs,
                             int asset_dir_count, dm_scene *s, dm_error *err)
{
    const char *where = path ? path : "(scene)";
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithOpts(json, &end, 1);
    if (!root) {
        dm_scene_defaults(s);
        snprintf(s->path, sizeof s->path, "%s", where);
        int line, col;
        const char *at = end ? end : cJSON_GetErrorPtr();
        if (!at) at = json;
        line_col(json, at, &line, &col);
        return dm_fail(err, DM_ERR_FORMAT, "%s:%d:%d: invalid JSON near \"%.20s\", expected a JSON object", where,
                       line, col, at);
    }
    dm_result r = scene_from_root(root, path, search, asset_dirs, asset_dir_count, s, err);
    cJSON_Delete(root);
    return r;
}

dm_result dm_scene_parse(const char *json, const char *path, dm_scene *s, dm_error *err)
{
    return parse_scene(json, path, false, NULL, 0, s, err);
}

dm_result dm_scene_read(const char *path, dm_scene *s, dm_error *err)
{
    return dm_scene_read_assets(path, NULL, 0, s, err);
}

dm_result dm_scene_read_assets(const char *path, const char *const *asset_dirs, int asset_dir_count, dm_scene *s,
                               dm_error *err)
{
    char *text = NULL;
    size_t size = 0;
    dm_scene_defaults(s);
    dm_result r = dm_input_read(path, DM_INPUT_JSON, &text, &size, err);
    if (r != DM_OK) return r;
    if (strlen(text) != size) {
        free(text);
        return dm_fail(err, DM_ERR_FORMAT, "%s: holds a NUL byte, expected JSON text", path);
    }
    r = parse_scene(text, path, true, asset_dirs, asset_dir_count, s, err);
    if (r == DM_OK) dm_hash_hex(text, size, s->file_hash);
    free(text);
    return r;
}

dm_result dm_scene_from_cjson(const cJSON *root, const char *text, size_t size, const char *path,
                              const char *const *asset_dirs, int asset_dir_count, dm_scene *s, dm_error *err)
{
    dm_result r = scene_from_root(root, path, true, asset_dirs, asset_dir_count, s, err);
    if (r == DM_OK) dm_hash_hex(text, size, s->file_hash);
    return r;
}
