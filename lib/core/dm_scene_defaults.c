/* dm_scene_defaults.c — the scene's names (effects, techniques, light types) and defaults
 * (core/dm_scene.h). */
#include "core/dm_scene.h"

#include <stdio.h>
#include <string.h>

static const char *const effect_names[DM_EFFECT_COUNT] = {
    "specular", "subsurface", "energy_conservation", "shadows", "environment_lighting", "glow", "tonemap",
    "translucency",
};

const char *dm_effect_name(dm_effect e)
{
    return (unsigned)e < DM_EFFECT_COUNT ? effect_names[e] : NULL;
}

int dm_effect_from_name(const char *name)
{
    for (int e = 0; e < DM_EFFECT_COUNT; ++e)
        if (name && strcmp(name, effect_names[e]) == 0) return e;
    return -1;
}

static const char *const technique_names[DM_SSS_TECHNIQUE_COUNT] = {"texture-space", "screen-space",
                                                                      "pre-integrated"};

const char *dm_sss_technique_name(dm_sss_technique t)
{
    return (unsigned)t < DM_SSS_TECHNIQUE_COUNT ? technique_names[t] : NULL;
}

bool dm_sss_technique_available(dm_sss_technique t)
{
    return t == DM_SSS_TEXTURE_SPACE || t == DM_SSS_SCREEN_SPACE || t == DM_SSS_PRE_INTEGRATED;
}

const char *dm_light_type_name(dm_light_type t)
{
    return t == DM_LIGHT_DIRECTIONAL ? "directional" : t == DM_LIGHT_POINT ? "point" : NULL;
}

void dm_scene_defaults(dm_scene *s)
{
    memset(s, 0, sizeof *s);
    s->roughness = 0.3f;
    s->rho_s = 0.18f;
    s->mm_per_unit = 50.0;
    s->env_intensity = 1.0f;
    s->env_background = true;
    for (int e = 0; e < DM_EFFECT_COUNT; ++e) s->effects[e] = true;
    s->effects[DM_EFFECT_TRANSLUCENCY] = false; /* off unless a scene asks */
    s->sss_technique = DM_SSS_TEXTURE_SPACE;
    s->screen_taps = DM_SCENE_SCREEN_TAPS_DEFAULT;
    s->translucency_intensity = 1.0f;
    dm_profile_gems3_skin(&s->profile);
    snprintf(s->profile_source, sizeof s->profile_source, "gems3-skin");
    s->blur_taps = 7;
    s->irradiance_size = 1024;
    s->mix = 0.5f;
    s->glow_threshold = 1.0f;
    s->glow_intensity = 0.1f;
    s->camera_eye[2] = 20.0f;
    s->camera_up[1] = 1.0f;
    s->fov_y_deg = 30.0f;
    s->width = 1280;
    s->height = 720;
}

