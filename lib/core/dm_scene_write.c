/* dm_scene_write.c — a scene back to JSON (dm_scene_to_json, core/dm_scene.h): what
 * dm_scene_parse reads, with every default written out. */
#include "core/dm_scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

static cJSON *vec3(const float v[3])
{
    double d[3] = {v[0], v[1], v[2]};
    return cJSON_CreateDoubleArray(d, 3);
}

/* An unfitted physical skin as read ({"skin": {…}}), the numbers at 17 digits. */
static cJSON *skin_json(const dm_scene_skin *k)
{
    cJSON *o = cJSON_CreateObject(), *in = cJSON_AddObjectToObject(o, "skin");
    if (k->preset[0]) cJSON_AddStringToObject(in, "preset", k->preset);
    for (int i = 0; i < k->key_count; ++i) {
        char num[32];
        snprintf(num, sizeof num, "%.17g", k->value[i]);
        cJSON_AddItemToObject(in, dm_skin_keys[k->key[i]], cJSON_CreateRaw(num));
    }
    return o;
}

/* The inline profile as the one profile writer writes it (dm_profile_to_json), verbatim:
 * 17 significant digits, so the scene's profile reads back exactly (cJSON's own printing
 * keeps 15 when they come within an ulp). NULL when it cannot be written. */
static cJSON *profile_json(const dm_profile *p)
{
    char *text = NULL;
    if (dm_profile_to_json(p, &text, NULL) != DM_OK) return NULL;
    size_t n = strlen(text);
    while (n && text[n - 1] == '\n') text[--n] = '\0';
    cJSON *o = cJSON_CreateRaw(text);
    free(text);
    return o;
}

dm_result dm_scene_to_json(const dm_scene *s, char **out, dm_error *err)
{
    *out = NULL;
    cJSON *r = cJSON_CreateObject();
    cJSON_AddStringToObject(r, "format", "dermis-scene");
    cJSON_AddNumberToObject(r, "version", DM_SCENE_VERSION);
    cJSON *m = cJSON_AddObjectToObject(r, "mesh");
    cJSON_AddStringToObject(m, "path", s->mesh);
    cJSON_AddNumberToObject(m, "mm_per_unit", s->mm_per_unit);
    if (s->mesh_name[0]) cJSON_AddStringToObject(m, "name", s->mesh_name);
    cJSON *mat = cJSON_AddObjectToObject(r, "material");
    cJSON_AddStringToObject(mat, "albedo", s->albedo);
    cJSON_AddStringToObject(mat, "normal_map", s->normal_map);
    cJSON_AddStringToObject(mat, "specular_map", s->specular_map);
    cJSON_AddStringToObject(mat, "roughness_map", s->roughness_map);
    cJSON_AddNumberToObject(mat, "roughness", s->roughness);
    cJSON_AddNumberToObject(mat, "rho_s", s->rho_s);
    /* written only when not the default, so a scene without it writes what it always did */
    if (s->albedo_from == DM_ALBEDO_FROM_SKIN) cJSON_AddStringToObject(mat, "albedo_from", "skin");
    cJSON *ls = cJSON_AddArrayToObject(r, "lights");
    for (int k = 0; k < s->light_count; ++k) {
        const dm_light *l = &s->lights[k];
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "type", dm_light_type_name(l->type));
        if (l->type == DM_LIGHT_POINT)
            cJSON_AddItemToObject(o, "position", vec3(l->position));
        else
            cJSON_AddItemToObject(o, "direction", vec3(l->direction));
        cJSON_AddItemToObject(o, "color", vec3(l->color));
        cJSON_AddNumberToObject(o, "intensity", l->intensity);
        cJSON_AddBoolToObject(o, "casts_shadow", l->casts_shadow);
        cJSON_AddItemToArray(ls, o);
    }
    cJSON *env = cJSON_AddObjectToObject(r, "environment");
    cJSON_AddStringToObject(env, "path", s->environment);
    cJSON_AddNumberToObject(env, "intensity", s->env_intensity);
    cJSON_AddNumberToObject(env, "rotation_deg", s->env_rotation_deg);
    cJSON_AddBoolToObject(env, "background", s->env_background);
    cJSON *alts = cJSON_AddArrayToObject(env, "alternatives");
    for (int k = 0; k < s->env_alternative_count; ++k)
        cJSON_AddItemToArray(alts, cJSON_CreateString(s->env_alternatives[k]));
    cJSON *fx = cJSON_AddObjectToObject(r, "effects");
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) {
        const char *name = dm_effect_name((dm_effect)e);
        if (e == DM_EFFECT_SUBSURFACE) {
            cJSON *o = cJSON_AddObjectToObject(fx, name);
            cJSON_AddBoolToObject(o, "enabled", s->effects[e]);
            cJSON_AddItemToObject(o, "profile", s->skin.given ? skin_json(&s->skin) : profile_json(&s->profile));
            cJSON_AddNumberToObject(o, "taps", s->blur_taps);
            cJSON_AddNumberToObject(o, "irradiance_size", s->irradiance_size);
            cJSON_AddNumberToObject(o, "mix", s->mix);
            cJSON_AddStringToObject(o, "technique", dm_sss_technique_name(s->sss_technique));
            cJSON_AddNumberToObject(o, "screen_taps", s->screen_taps);
        } else if (e == DM_EFFECT_GLOW) {
            cJSON *o = cJSON_AddObjectToObject(fx, name);
            cJSON_AddBoolToObject(o, "enabled", s->effects[e]);
            cJSON_AddNumberToObject(o, "threshold", s->glow_threshold);
            cJSON_AddNumberToObject(o, "intensity", s->glow_intensity);
        } else if (e == DM_EFFECT_TONEMAP) {
            cJSON *o = cJSON_AddObjectToObject(fx, name);
            cJSON_AddBoolToObject(o, "enabled", s->effects[e]);
            cJSON_AddNumberToObject(o, "exposure", s->exposure);
        } else if (e == DM_EFFECT_TRANSLUCENCY) {
            cJSON *o = cJSON_AddObjectToObject(fx, name);
            cJSON_AddBoolToObject(o, "enabled", s->effects[e]);
            cJSON_AddNumberToObject(o, "intensity", s->translucency_intensity);
        } else {
            cJSON_AddBoolToObject(fx, name, s->effects[e]);
        }
    }
    cJSON *cam = cJSON_AddObjectToObject(r, "camera");
    cJSON_AddItemToObject(cam, "eye", vec3(s->camera_eye));
    cJSON_AddItemToObject(cam, "target", vec3(s->camera_target));
    cJSON_AddItemToObject(cam, "up", vec3(s->camera_up));
    cJSON_AddNumberToObject(cam, "fov_y_deg", s->fov_y_deg);
    cJSON *o = cJSON_AddObjectToObject(r, "output");
    cJSON_AddNumberToObject(o, "width", s->width);
    cJSON_AddNumberToObject(o, "height", s->height);
    *out = cJSON_Print(r);
    cJSON_Delete(r);
    if (!*out) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: cannot print the scene as JSON", s->path);
    return DM_OK;
}
