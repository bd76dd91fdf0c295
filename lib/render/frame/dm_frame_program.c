/* dm_frame_program.c — a pass's program: its shader file after common.glsl (embedded, or from
 * the shader folder), the defines the frame calls for (effects, lights, sizes, techniques),
 * the row's extra defines, and every sampler on its fixed unit (dm_frame.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_level_sum.h"
#include "render/frame/dm_frame.h"
#include "render/frame/dm_frame_bind.h"
#include "render/gpu/dm_gpu_program.h"
#include "render/input/dm_render_shaders.h"

static void set_sampler_units(GLuint p)
{
    static const struct {
        const char *name;
        int unit;
    } units[] = {{"u_albedo", UNIT_ALBEDO},     {"u_normal_map", UNIT_NORMAL},   {"u_specular_map", UNIT_SPECULAR},
                 {"u_roughness_map", UNIT_ROUGHNESS}, {"u_beckmann", UNIT_BECKMANN}, {"u_rho_dt", UNIT_RHO_DT},
                 {"u_env_brdf", UNIT_ENV_BRDF},   {"u_shadow0", UNIT_SHADOW},
                 {"u_shadow1", UNIT_SHADOW + 1},   {"u_shadow2", UNIT_SHADOW + 2},  {"u_shadow3", UNIT_SHADOW + 3},
                 {"u_src", UNIT_SRC},             {"u_stretch", UNIT_STRETCH},     {"u_mask", UNIT_MASK},
                 {"u_depth", UNIT_DEPTH},         {"u_background", UNIT_BACKGROUND},
                 {"u_env_array", UNIT_ENV_ARRAY}, {"u_diffusion", UNIT_DIFFUSION}, {"u_aux", UNIT_SS_AUX},
                 {"u_glow", UNIT_GLOW},           {"u_spec", UNIT_SS_SPEC},
                 {"u_tdepth0", UNIT_TDEPTH0},     {"u_tdepth1", UNIT_TDEPTH0 + 1}, {"u_tdepth2", UNIT_TDEPTH0 + 2},
                 {"u_tdepth3", UNIT_TDEPTH0 + 3}, {"u_preint", UNIT_PREINT},   {"u_curvature", UNIT_CURVATURE},
                 {"u_seam", UNIT_SEAM},           {"u_cover", UNIT_COVER},         {"u_thin", UNIT_THIN},
                 {"u_gather_index", UNIT_GATHER_INDEX}, {"u_gather_taps", UNIT_GATHER_TAPS},
                 {"u_points", UNIT_POINTS},
                 {"u_cuts", UNIT_CUTS}};
    glUseProgram(p);
    for (size_t i = 0; i < sizeof units / sizeof units[0]; ++i) {
        GLint loc = glGetUniformLocation(p, units[i].name);
        if (loc >= 0) glUniform1i(loc, units[i].unit);
    }
    /* the arrays: u_gbuf0..3 (on the units dmr_gbuffer_unit picks), u_env_level[], u_level[] */
    const struct {
        const char *format;
        int first, count;
    } arrays[] = {{"u_gbuf%d", dmr_gbuffer_unit(p), 4},
                  {"u_env_level[%d]", UNIT_ENV_LEVEL0, DM_RENDER_ENV_LEVELS_MAX},
                  {"u_level[%d]", UNIT_LEVEL0, DM_PROFILE_MAX_GAUSSIANS}}; /* common.glsl's u_level[8] */
    char name[32];
    for (size_t a = 0; a < sizeof arrays / sizeof arrays[0]; ++a)
        for (int i = 0; i < arrays[a].count; ++i) {
            snprintf(name, sizeof name, arrays[a].format, i);
            GLint loc = glGetUniformLocation(p, name);
            if (loc >= 0) glUniform1i(loc, arrays[a].first + i);
        }
}

/* "#define NAME(i) ((i) == 0 ? v0 : (i) == 1 ? v1 : ... : v_{n-1})" for v[0..n-1] (n >= 1) */
static size_t index_macro(char *out, size_t size, const char *name, const int *v, int n)
{
    size_t k = (size_t)snprintf(out, size, "#define %s(i) (", name);
    for (int i = 0; i + 1 < n && k < size; ++i) k += (size_t)snprintf(out + k, size - k, "(i) == %d ? %d : ", i, v[i]);
    if (k < size) k += (size_t)snprintf(out + k, size - k, "%d)\n", v[n - 1]);
    return k < size ? k : size - 1;
}

/* The lights' fixed facts as constants (dm_renderer_set_scene may change neither): which shadow
 * map each light has (DM_LIGHT_SHADOW(i), -1: none), whether it is a point light
 * (DM_LIGHT_POINT(i)), the light of each shadow map (DM_SHADOW_LIGHT(j)), and which material
 * maps exist. With these constant the lights' unrolled loops carry no branch on a uniform:
 * llvmpipe runs both sides of those, so every light paid for the shadow lookup and every
 * frame for the roughness map's fetch (docs/render-quality.md). */
static size_t light_defines(const dmr_frame *f, char *out, size_t size)
{
    int shadow[DM_SCENE_MAX_LIGHTS + 1], point[DM_SCENE_MAX_LIGHTS + 1], light[DM_SCENE_MAX_LIGHTS + 1];
    int n = f->scene.light_count > 0 ? f->scene.light_count : 1, m = f->plan.shadow_count > 0 ? f->plan.shadow_count : 1;
    for (int i = 0; i < n; ++i) {
        shadow[i] = -1;
        point[i] = i < f->scene.light_count && f->scene.lights[i].type != DM_LIGHT_DIRECTIONAL;
    }
    for (int j = 0; j < f->plan.shadow_count; ++j) shadow[f->plan.shadow_light[j]] = j;
    for (int j = 0; j < m; ++j) light[j] = j < f->plan.shadow_count ? f->plan.shadow_light[j] : 0;
    size_t k = index_macro(out, size, "DM_LIGHT_SHADOW", shadow, n);
    k += index_macro(out + k, size - k, "DM_LIGHT_POINT", point, n);
    k += index_macro(out + k, size - k, "DM_SHADOW_LIGHT", light, m);
    if (f->has_normal_map) k += (size_t)snprintf(out + k, size - k, "#define DM_NORMAL_MAP 1\n");
    if (f->has_roughness_map && k < size) k += (size_t)snprintf(out + k, size - k, "#define DM_ROUGHNESS_MAP 1\n");
    return k < size ? k : size - 1;
}

/* The defines every program of this frame shares, then `extra`. */
static void frame_defines(const dmr_frame *f, const char *extra, char *defines, size_t size)
{
    const dm_render_plan *p = &f->plan;
    snprintf(defines, size,
             "%s%s%s%s#define DM_LIGHTS %d\n#define DM_SHADOW_MAPS %d\n#define DM_TAPS %d\n#define DM_LEVELS %d\n#define DM_ENV_LEVELS %d\n"
             "#define DM_SHADOW_TAPS %d\n%s",
             p->texture_space ? "#define DM_SUBSURFACE 1\n" : "",
             p->effects[DM_EFFECT_SPECULAR] ? "#define DM_SPECULAR 1\n" : "",
             p->energy_conservation_active ? "#define DM_ENERGY 1\n" : "",
             p->effects[DM_EFFECT_ENVIRONMENT_LIGHTING] ? "#define DM_ENV 1\n" : "", f->scene.light_count,
             p->shadow_count, f->taps, p->texture_space ? f->profile.count : 0, f->env_level_count,
             f->shadow_taps, f->tex_env_array ? "#define DM_ENV_ARRAY 1\n" : "");
    size_t n = strlen(defines);
    n += light_defines(f, defines + n, size - n);
    /* appended only when on */
    if (p->screen_space)
        n += (size_t)snprintf(defines + n, size - n, "#define DM_SCREEN_SPACE 1\n#define DM_SS_TAPS %d\n#define DM_SS_ROWS %d\n",
                              f->ss_taps, f->ss_rows);
    if (p->pre_integrated) n += (size_t)snprintf(defines + n, size - n, "#define DM_PRE_INTEGRATED 1\n");
    if (p->translucency_active)
        n += (size_t)snprintf(defines + n, size - n, "#define DM_TRANSLUCENCY 1\n#define DM_TRANS_GAUSSIANS %d\n",
                              f->profile.count);
    if (p->glow_in_tonemap) n += (size_t)snprintf(defines + n, size - n, "#define DM_GLOW 1\n");
    if (f->spec_in_normal) n += (size_t)snprintf(defines + n, size - n, "#define DM_SPEC_IN_NORMAL 1\n");
    if (f->diffusion_sum) n += (size_t)snprintf(defines + n, size - n, "#define DM_DIFFUSION_SUM 1\n");
    if (f->tex_seam && p->texture_space) n += (size_t)snprintf(defines + n, size - n, "#define DM_SEAM 1\n");
    if (f->tex_thin && p->texture_space)
        n += (size_t)snprintf(defines + n, size - n, "#define DM_THIN 1\n#define DM_THIN_CUT %d.0\n", DM_LEVEL_SUM_THIN_CUT);
    if (f->tex_gather_index && p->texture_space) n += (size_t)snprintf(defines + n, size - n, "#define DM_GATHER 1\n");
    if (extra) snprintf(defines + n, size - n, "%s", extra);
}

dm_result dmr_frame_program(dmr_frame *f, const char *file, const char *extra, GLuint *out, dm_error *err)
{
    char defines[2048];
    frame_defines(f, extra, defines, sizeof defines);
    const char *dir = f->shader_dir[0] ? f->shader_dir : NULL;
    char *common = NULL, *src = NULL;
    dm_result rc = dm_render_shader_source(dir, "common.glsl", &common, err);
    if (rc == DM_OK) rc = dm_render_shader_source(dir, file, &src, err);
    /* a pass file without a vertex stage takes common.glsl's full-screen triangle */
    if (rc == DM_OK && !strstr(src, "DM_VERTEX"))
        snprintf(defines + strlen(defines), sizeof defines - strlen(defines), "#define DM_FULLSCREEN 1\n");
    /* one that rasterises the mesh takes common.glsl's attributes and varyings for it */
    else if (rc == DM_OK && strstr(src, "dm_mesh_vertex(") && !strstr(defines, "DM_FULLSCREEN"))
        snprintf(defines + strlen(defines), sizeof defines - strlen(defines), "#define DM_MESH_VERTEX 1\n");
    static const char *const attribs[4] = {"a_position", "a_normal", "a_tangent", "a_uv"};
    if (rc == DM_OK) rc = dmg_program(&f->gpu, file, defines, common, src, attribs, 4, out, err);
    free(common);
    free(src);
    if (rc != DM_OK) return rc;
    set_sampler_units(*out);
    return dmg_check(file, err);
}
