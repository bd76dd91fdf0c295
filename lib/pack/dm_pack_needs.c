#include "pack/dm_pack_needs.h"

#include <stdio.h>
#include <string.h>

/* The table. Order is the order dermis-pack writes entries and --explain lists them. */
static const dm_pack_need needs[] = {
    {"scene", DM_PACK_SCENE, -1, 0, DM_NEED_ALWAYS, "the scene itself: effects, lights, camera, parameters", false},
    {"mesh.vertices", DM_PACK_MESH_VERTICES, -1, 0, DM_NEED_ALWAYS,
     "the head, split by (position, uv, normal), with tangent frames", false},
    {"mesh.indices", DM_PACK_MESH_INDICES, -1, 0, DM_NEED_ALWAYS, "its triangles", false},
    {"albedo", DM_PACK_TEXTURE, DM_TEX_RGBA8_SRGB, 0, DM_NEED_IF_ALBEDO, "diffuse colour (sRGB)", false},
    {"normal", DM_PACK_TEXTURE, DM_TEX_RGBA8, 0, DM_NEED_IF_NORMAL_MAP,
     "tangent-space normal map, lighting in every pass", false},
    {"specular", DM_PACK_TEXTURE, DM_TEX_R8, DM_FX(DM_EFFECT_SPECULAR) | DM_FX(DM_EFFECT_ENERGY_CONSERVATION),
     DM_NEED_IF_SPECULAR_MAP, "specular intensity map (scales rho_s)", false},
    {"roughness", DM_PACK_TEXTURE, DM_TEX_R8,
     DM_FX(DM_EFFECT_SPECULAR) | DM_FX(DM_EFFECT_ENERGY_CONSERVATION) | DM_FX(DM_EFFECT_ENVIRONMENT_LIGHTING),
     DM_NEED_IF_ROUGHNESS_MAP, "Beckmann roughness map", false},
    {"lut.beckmann", DM_PACK_TEXTURE, DM_TEX_R8, DM_FX(DM_EFFECT_SPECULAR), DM_NEED_ALWAYS,
     "Beckmann D(N.H, m) as 0.5*D^0.1, 8-bit (KS specular)", false},
    {"lut.rho_dt", DM_PACK_TEXTURE, DM_TEX_R32F, DM_FX(DM_EFFECT_ENERGY_CONSERVATION), DM_NEED_ALWAYS,
     "rho_dt(N.L, m): light the specular takes, 1 - rho_s*rho_dt in and out", false},
    {"lut.env_brdf", DM_PACK_TEXTURE, DM_TEX_RG32F, DM_FX(DM_EFFECT_ENVIRONMENT_LIGHTING), DM_NEED_ALWAYS,
     "split-sum scale and bias of F0 for environment specular", false},
    {"profile", DM_PACK_PROFILE, -1, DM_FX(DM_EFFECT_SUBSURFACE) | DM_FX(DM_EFFECT_TRANSLUCENCY), DM_NEED_ALWAYS,
     "sum-of-Gaussians diffusion profile: blur variances and weights, transmittance T(d)", false},
    {"stretch", DM_PACK_TEXTURE, DM_TEX_RG32F, DM_FX(DM_EFFECT_SUBSURFACE), DM_NEED_IF_TEXTURE_SPACE,
     "UV stretch (u, v per mm) and its blurred chain, one layer per Gaussian", false},
    {"stretch.mask", DM_PACK_TEXTURE, DM_TEX_R8, DM_FX(DM_EFFECT_SUBSURFACE), DM_NEED_IF_TEXTURE_SPACE,
     "chart coverage mask (gutter handling)", false},
    {"seam", DM_PACK_TEXTURE, DM_TEX_RGBA32F, DM_FX(DM_EFFECT_SUBSURFACE), DM_NEED_IF_TEXTURE_SPACE,
     "seam map: per gutter texel a blur reaches, where the surface continues across the UV seam (u, v, 1, mm); "
     "the renderer uses it where the thin gather is not (levels summed per pixel, reduced levels)", true},
    {"thin", DM_PACK_TEXTURE, DM_TEX_RGBA32F, DM_FX(DM_EFFECT_SUBSURFACE), DM_NEED_IF_TEXTURE_SPACE,
     "thin-part map: per texel up to 2 surfaces across a thin part or a fold (u, v, mm, 1), N x 2N", true},
    {"thin.half", DM_PACK_TEXTURE, DM_TEX_RGBA32F, DM_FX(DM_EFFECT_SUBSURFACE), DM_NEED_IF_TEXTURE_SPACE,
     "the thin-part map at half the irradiance size (N/2 x N)", true},
    {"gather.index", DM_PACK_TEXTURE, DM_TEX_RGBA32F, DM_FX(DM_EFFECT_SUBSURFACE), DM_NEED_IF_TEXTURE_SPACE,
     "thin gather: per texel (first tap's row, taps of the first gathered level, of the second, first tap's column), N x N", true},
    {"gather.taps", DM_PACK_TEXTURE, DM_TEX_RG32F, DM_FX(DM_EFFECT_SUBSURFACE), DM_NEED_IF_TEXTURE_SPACE,
     "thin gather: 4096 wide; the header (first level, levels), (-2, sites), the sites (u, v), the taps (site, weight)", true},
    {"gather.half.index", DM_PACK_TEXTURE, DM_TEX_RGBA32F, DM_FX(DM_EFFECT_SUBSURFACE), DM_NEED_IF_TEXTURE_SPACE,
     "the thin gather's index at half the irradiance size (N/2 x N/2)", true},
    {"gather.half.taps", DM_PACK_TEXTURE, DM_TEX_RG32F, DM_FX(DM_EFFECT_SUBSURFACE), DM_NEED_IF_TEXTURE_SPACE,
     "the thin gather's taps at half the irradiance size", true},
    {"sss.kernel", DM_PACK_TEXTURE, DM_TEX_RGBA32F, DM_FX(DM_EFFECT_SUBSURFACE), DM_NEED_IF_SCREEN_SPACE,
     "separable 1-D kernels fitted to the profile, one row per size of pixel (taps x rows: rgb weights, a = offset px; t_range: the rows' mm per pixel)", false},
    {"sss.preintegrated", DM_PACK_TEXTURE, DM_TEX_RGBA32F, DM_FX(DM_EFFECT_SUBSURFACE), DM_NEED_IF_PRE_INTEGRATED,
     "pre-integrated diffuse D(N.L, curvature) for the profile (Penner 2011; rgb, a = 1)", false},
    {"sss.curvature", DM_PACK_TEXTURE, DM_TEX_R32F, DM_FX(DM_EFFECT_SUBSURFACE), DM_NEED_IF_PRE_INTEGRATED,
     "mean curvature per texel, 1/mm (cotangent Laplacian, smoothed over the profile's scale)", false},
    {"env.sh", DM_PACK_ENV_SH, -1, DM_FX(DM_EFFECT_ENVIRONMENT_LIGHTING), DM_NEED_ALWAYS,
     "diffuse environment light, 9 RGB SH coefficients", false},
    {"env.specular", DM_PACK_TEXTURE, DM_TEX_RGBA32F, DM_FX(DM_EFFECT_ENVIRONMENT_LIGHTING), DM_NEED_ALWAYS,
     "environment prefiltered for Beckmann roughness levels", false},
    {"env.background", DM_PACK_TEXTURE, DM_TEX_RGBA32F, 0, DM_NEED_IF_BACKGROUND,
     "the environment shown behind the head", false},
};

const dm_pack_need *dm_pack_needs(int *count)
{
    *count = (int)(sizeof needs / sizeof needs[0]);
    return needs;
}

static const dm_pack_need *find_row(const char *entry)
{
    for (size_t k = 0; k < sizeof needs / sizeof needs[0]; ++k)
        if (strcmp(needs[k].entry, entry) == 0) return &needs[k];
    return NULL;
}

/* Environment rows are those named "env.<rest>". */
static bool per_env(const dm_pack_need *n)
{
    return strncmp(n->entry, "env.", 4) == 0;
}

const dm_pack_need *dm_pack_need_find_copy(const char *entry, int *copy)
{
    if (copy) *copy = 0;
    const dm_pack_need *n = find_row(entry);
    if (n) return n;
    /* "env<k>.<rest>" with k in [1, max] written without a leading zero */
    if (strncmp(entry, "env", 3) != 0 || entry[3] < '1' || entry[3] > '9') return NULL;
    int k = 0;
    const char *p = entry + 3;
    while (*p >= '0' && *p <= '9' && k <= DM_SCENE_MAX_ENV_ALTERNATIVES) k = k * 10 + (*p++ - '0');
    if (*p != '.' || k > DM_SCENE_MAX_ENV_ALTERNATIVES) return NULL;
    char base[DM_PACK_NAME_SIZE];
    if (snprintf(base, sizeof base, "env%s", p) >= (int)sizeof base) return NULL;
    n = find_row(base);
    if (!n || !per_env(n)) return NULL;
    if (copy) *copy = k;
    return n;
}

const dm_pack_need *dm_pack_need_find(const char *entry)
{
    return dm_pack_need_find_copy(entry, NULL);
}

int dm_pack_need_copies(const dm_pack_need *n, const dm_scene *s)
{
    return per_env(n) ? 1 + s->env_alternative_count : 1;
}

char *dm_pack_need_entry_name(const dm_pack_need *n, int copy, char *out)
{
    if (copy == 0 || !per_env(n))
        snprintf(out, DM_PACK_NAME_SIZE, "%s", n->entry);
    else
        snprintf(out, DM_PACK_NAME_SIZE, "env%d%s", copy, n->entry + 3);
    return out;
}

bool dm_pack_entry_applies(const char *entry, const dm_scene *s)
{
    int copy;
    const dm_pack_need *n = dm_pack_need_find_copy(entry, &copy);
    return n && copy < dm_pack_need_copies(n, s) && dm_pack_need_applies(n, s);
}

bool dm_pack_need_applies(const dm_pack_need *n, const dm_scene *s)
{
    bool fx = n->effects == 0;
    for (int e = 0; e < DM_EFFECT_COUNT; ++e)
        if ((n->effects & DM_FX(e)) && s->effects[e]) fx = true;
    if (!fx) return false;
    switch (n->when) {
    case DM_NEED_ALWAYS: return true;
    case DM_NEED_IF_ALBEDO: return s->albedo[0] != '\0';
    case DM_NEED_IF_NORMAL_MAP: return s->normal_map[0] != '\0';
    case DM_NEED_IF_SPECULAR_MAP: return s->specular_map[0] != '\0';
    case DM_NEED_IF_ROUGHNESS_MAP: return s->roughness_map[0] != '\0';
    case DM_NEED_IF_BACKGROUND: return s->environment[0] != '\0' && s->env_background;
    case DM_NEED_IF_TEXTURE_SPACE: return s->sss_technique == DM_SSS_TEXTURE_SPACE;
    case DM_NEED_IF_SCREEN_SPACE: return s->sss_technique == DM_SSS_SCREEN_SPACE;
    case DM_NEED_IF_PRE_INTEGRATED: return s->sss_technique == DM_SSS_PRE_INTEGRATED;
    }
    return false;
}

const char *dm_need_when_text(dm_need_when w)
{
    switch (w) {
    case DM_NEED_ALWAYS: return "";
    case DM_NEED_IF_ALBEDO: return "albedo map";
    case DM_NEED_IF_NORMAL_MAP: return "normal map";
    case DM_NEED_IF_SPECULAR_MAP: return "specular map";
    case DM_NEED_IF_ROUGHNESS_MAP: return "roughness map";
    case DM_NEED_IF_BACKGROUND: return "environment with background";
    case DM_NEED_IF_TEXTURE_SPACE: return "technique texture-space";
    case DM_NEED_IF_SCREEN_SPACE: return "technique screen-space";
    case DM_NEED_IF_PRE_INTEGRATED: return "technique pre-integrated";
    }
    return "";
}
