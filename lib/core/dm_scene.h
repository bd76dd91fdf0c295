/* dm_scene.h — the scene: what to show and which effects to simulate.
 *
 * A scene file (JSON, strict) names the mesh and maps, the lights, the environment, the
 * camera, the output size and the effects. From the effects follow what is baked and
 * packed (dermis-pack) and which passes run (lib/render): an effect that is off costs
 * nothing anywhere. This struct is the parsed, validated form; zero-initialised fields
 * are not valid on their own: use dm_scene_defaults() then override.
 *
 * Units: mm_per_unit converts mesh units to millimetres; variances in mm²; angles in
 * degrees; colours linear RGB; intensities are multipliers of colour.
 * Paths are stored resolved against the scene file's folder.
 */
#ifndef DM_SCENE_H
#define DM_SCENE_H

#include <stdbool.h>

#include "core/dm_hash.h"
#include "core/dm_profile.h"
#include "core/dm_skin_keys.h"
#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_SCENE_PATH_SIZE = 1024, DM_SCENE_MAX_LIGHTS = 8, DM_SCENE_MAX_ENV_ALTERNATIVES = 7 };
enum { DM_SCENE_NAME_SIZE = 128 };
/* The scene file version this dermis reads and writes (the policy: docs/dermis-scene.5.md). */
enum { DM_SCENE_VERSION = 1 };

typedef enum dm_effect {
    DM_EFFECT_SPECULAR = 0,         /* KS specular (Beckmann LUT, Fresnel, spec map) */
    DM_EFFECT_SUBSURFACE,           /* texture-space diffusion (irradiance, blurs, stretch) */
    DM_EFFECT_ENERGY_CONSERVATION,  /* 1 − ρs·ρdt on light in and out (rho_dt LUT) */
    DM_EFFECT_SHADOWS,              /* shadow maps for lights that cast */
    DM_EFFECT_ENVIRONMENT_LIGHTING, /* SH diffuse + prefiltered specular (env bake, env-BRDF) */
    DM_EFFECT_GLOW,                 /* bright pass, blur, add */
    DM_EFFECT_TONEMAP,              /* exposure, filmic curve, sRGB */
    DM_EFFECT_TRANSLUCENCY,         /* light through thin parts: shadow-map thickness through the
                                     * profile's transmittance (off unless a scene asks) */
    DM_EFFECT_COUNT
} dm_effect;

/* "specular", "subsurface", ... as in the scene file; NULL for out-of-range values. */
const char *dm_effect_name(dm_effect e);
/* The effect with that scene-file name, or -1. */
int dm_effect_from_name(const char *name);

/* How subsurface scattering is simulated (effects.subsurface.technique). */
typedef enum dm_sss_technique {
    DM_SSS_TEXTURE_SPACE = 0, /* "texture-space": d'Eon & Luebke, the default */
    DM_SSS_SCREEN_SPACE,      /* "screen-space": Jimenez et al. 2015 separable SSS */
    DM_SSS_PRE_INTEGRATED,    /* "pre-integrated": Penner 2011, one pass through a baked table */
    DM_SSS_TECHNIQUE_COUNT
} dm_sss_technique;

/* "texture-space", "screen-space", "pre-integrated"; NULL for out-of-range values. */
const char *dm_sss_technique_name(dm_sss_technique t);
/* Whether the technique is implemented (parse-able names that are not are refused). */
bool dm_sss_technique_available(dm_sss_technique t);

/* The screen-space kernel's tap counts a scene may ask for (effects.subsurface.screen_taps). */
enum { DM_SCENE_SCREEN_TAPS_DEFAULT = 17 };
#define DM_SCENE_SCREEN_TAPS_LIST {11, 17, 25}

typedef enum dm_light_type { DM_LIGHT_DIRECTIONAL, DM_LIGHT_POINT } dm_light_type;

/* "directional" or "point"; NULL for out-of-range values. */
const char *dm_light_type_name(dm_light_type t);

typedef struct dm_light {
    dm_light_type type;
    float direction[3]; /* directional: unit vector the light travels *from* the head towards
                         * the light (i.e. L), mesh space */
    float position[3];  /* point: mesh units */
    float color[3];     /* linear RGB */
    float intensity;
    bool casts_shadow;
} dm_light;

/* The physical skin a scene names as its profile ("profile": {"skin": {…}}). The scene reader
 * (core) only checks the names and stores the numbers: the model and its ranges are offline
 * (bake/dm_skin_spec.h), so the packer evaluates it and fits the profile when it packs
 * (profile_source "skin" until then, and `profile` is the gems3-skin stand-in meanwhile).
 * Keys: core/dm_skin_keys.h; "preset" a starting point the keys override. */
typedef struct dm_scene_skin {
    bool given;
    char preset[DM_SKIN_PRESET_NAME_SIZE];  /* "" or a preset name */
    int key_count;                          /* [0, DM_SKIN_KEY_COUNT] */
    int key[DM_SKIN_KEY_COUNT];             /* index into dm_skin_keys, in file order */
    double value[DM_SKIN_KEY_COUNT];
} dm_scene_skin;

/* Where the diffuse colour comes from (material.albedo_from). */
typedef enum dm_albedo_from {
    DM_ALBEDO_FROM_MAP = 0, /* "map": the albedo map as it is (the default) */
    DM_ALBEDO_FROM_SKIN     /* "skin": the physical skin's total diffuse reflectance per channel
                             * times the map's luminance detail (bake/dm_albedo_skin.h); needs a
                             * {"skin": {…}} profile and an albedo map, baked by the packer */
} dm_albedo_from;

typedef struct dm_scene {
    char path[DM_SCENE_PATH_SIZE]; /* the scene file itself */
    char file_hash[DM_HASH_HEX_SIZE]; /* its content hash (dm_hash_hex) from the one read of
                                       * dm_scene_read*; "" when parsed from a string */
    /* mesh and maps */
    char mesh[DM_SCENE_PATH_SIZE];
    char mesh_name[DM_SCENE_NAME_SIZE];     /* glTF meshes: only those of this name; "" = all */
    char albedo[DM_SCENE_PATH_SIZE];        /* sRGB colour map, or "" for constant white */
    char normal_map[DM_SCENE_PATH_SIZE];    /* tangent-space, green up, or "" */
    char specular_map[DM_SCENE_PATH_SIZE];  /* grey intensity (scales rho_s), or "" */
    char roughness_map[DM_SCENE_PATH_SIZE]; /* grey m in [0, 1], or "" to use roughness */
    float roughness;                        /* constant m when no map (default 0.3) */
    float rho_s;                            /* specular scale (default 0.18) */
    dm_albedo_from albedo_from;             /* default DM_ALBEDO_FROM_MAP */
    double mm_per_unit;                     /* default 50 (the Lee Perry-Smith head) */

    int light_count;
    dm_light lights[DM_SCENE_MAX_LIGHTS];

    /* environment */
    char environment[DM_SCENE_PATH_SIZE]; /* equirect .hdr/.exr, or "" */
    float env_intensity;                  /* default 1 */
    float env_rotation_deg;               /* about +Y, default 0 */
    bool env_background;                  /* shown behind the head, default true */
    /* more maps to choose among (the viewer's selector): packed as env<k>.* for k = 1..count,
     * baked like the main one; the scene's intensity, rotation and background apply to each */
    int env_alternative_count;            /* [0, DM_SCENE_MAX_ENV_ALTERNATIVES], default 0 */
    char env_alternatives[DM_SCENE_MAX_ENV_ALTERNATIVES][DM_SCENE_PATH_SIZE];

    bool effects[DM_EFFECT_COUNT];
    /* subsurface */
    dm_profile profile;      /* default gems3-skin; from "profile": "gems3-skin" or a JSON path */
    char profile_source[DM_SCENE_PATH_SIZE]; /* "gems3-skin", "inline", "skin" or the file */
    dm_scene_skin skin;      /* "profile": {"skin": {…}}: the parameters, stored, not evaluated */
    int blur_taps;           /* taps per separable pass, odd, default 7 (the chapter's) */
    int irradiance_size;     /* texture-space resolution, default 1024 */
    float mix;               /* pre/post-scatter albedo mix, default 0.5 */
    dm_sss_technique sss_technique; /* default texture-space */
    int screen_taps;         /* screen-space kernel taps: 11, 17 (default) or 25 */
    /* translucency */
    float translucency_intensity; /* multiplies the transmitted light, [0, 100], default 1 */
    /* tonemap */
    float exposure;          /* stops, default 0 */
    /* glow */
    float glow_threshold;    /* default 1 */
    float glow_intensity;    /* default 0.1 */

    /* camera (look-at, mesh units) */
    float camera_eye[3], camera_target[3], camera_up[3];
    float fov_y_deg;         /* default 30 */
    int width, height;       /* output size, default 1280x720 */
} dm_scene;

/* Scene file (JSON), every key optional unless marked; see docs/dermis-scene.5.md:
 *   { "format": "dermis-scene", "version": 1,
 *     "mesh": { "path": REQUIRED, "mm_per_unit": (0, 1e6], "name": glTF mesh name or "" },
 *     "material": { "albedo", "normal_map", "specular_map", "roughness_map": paths or "",
 *                   "roughness": [0, 1], "rho_s": [0, 1], "albedo_from": "map" | "skin" (needs
 *                   a {"skin": {…}} profile) },
 *     "lights": [ { "type": "directional"|"point" REQUIRED, "direction"|"position" REQUIRED,
 *                   "color": [3 × [0, 1e6]], "intensity": [0, 1e6], "casts_shadow": bool } ] (≤ 8),
 *     "environment": { "path", "intensity": [0, 1e6], "rotation_deg": [-360, 360], "background",
 *                      "alternatives": [ ≤ 7 non-empty paths ] (needs "path") },
 *     "effects": REQUIRED { NAME: true | false | { "enabled": bool (default true), params } },
 *        subsurface params: "profile" ("gems3-skin", a profile JSON path, an inline profile
 *        object, or a physical skin {"skin": {"preset": NAME, KEY: number, …}} with the keys
 *        of core/dm_skin_keys.h: melanin, eumelanin, blood required without a preset; its
 *        ranges are checked and its profile fitted by the packer), "taps" odd [3, 63], "irradiance_size" [64, 8192], "mix" [0, 1],
 *        "technique" "texture-space" | "screen-space" | "pre-integrated",
 *        "screen_taps" 11 | 17 | 25;
 *        translucency: "intensity" [0, 100] (off unless listed, also in dm_scene_defaults);
 *        glow: "threshold" [0, 1e6], "intensity" [0, 100]; tonemap: "exposure" [-20, 20].
 *        Exactly the effects listed as on are on; the others are off.
 *     "camera": { "eye", "target", "up" (not parallel to the view), "fov_y_deg": [1, 179] },
 *     "output": { "width", "height": [1, 16384] } }
 * Directional light directions are normalised on reading. environment_lighting needs an
 * environment path. Unknown keys and keys given twice are errors. */

/* Fills s with every default (all effects on, no lights, gems3-skin, 1280x720 ...). */
void dm_scene_defaults(dm_scene *s);

/* Parses a scene file strictly: an unknown key, a wrong type or an out-of-range value is
 * an error naming the JSON path, the value and what was expected, as
 * "FILE: $.effects.subsurface.taps: 4 is not an odd integer in [3, 63]".
 * Relative file paths resolve against the scene file's folder; one missing there is looked
 * up in the asset search path: DERMIS_ASSETS (folders separated by ':'), then the build's
 * default (the Makefile's ASSETS, absolute). A path found nowhere is DM_ERR_FILE_OPEN naming
 * every place looked. */
dm_result dm_scene_read(const char *path, dm_scene *s, dm_error *err);
/* dm_scene_read with asset_dirs (asset_dir_count folders, a tool's --assets) searched
 * first, before DERMIS_ASSETS and the default. */
dm_result dm_scene_read_assets(const char *path, const char *const *asset_dirs, int asset_dir_count, dm_scene *s,
                               dm_error *err);
/* dm_scene_read_assets of a file already read (`text`, `size` bytes, for the scene's hash) and
 * parsed (`root`): dermis-check parses a JSON file once to tell a scene from a profile. */
struct cJSON;
dm_result dm_scene_from_cjson(const struct cJSON *root, const char *text, size_t size, const char *path,
                              const char *const *asset_dirs, int asset_dir_count, dm_scene *s, dm_error *err);
/* From a string, without touching the disk: relative paths resolve against `path`'s folder
 * (also used in messages), whether or not the file exists (packs re-read their scene so). */
dm_result dm_scene_parse(const char *json, const char *path, dm_scene *s, dm_error *err);

/* The scene as a complete, self-contained scene file (every key written, the profile
 * inline, paths as stored): dm_scene_parse of it gives back the same struct. *out is
 * malloc'd, NUL-terminated; free it with free(). */
dm_result dm_scene_to_json(const dm_scene *s, char **out, dm_error *err);

#ifdef __cplusplus
}
#endif
#endif
