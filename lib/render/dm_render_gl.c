/* dm_render_gl.c — GL helpers: pack formats on the GL side, texture uploads, shader programs
 * (common.glsl + the pass, the plan's defines, fixed sampler units), small matrix helpers. */
#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/dm_render_internal.h"
#include "render/dm_render_shaders.h"

/* ---- texture formats ------------------------------------------------------------------ */


const fmt_gl dmr_formats[DM_TEX_FORMAT_COUNT] = {
    [DM_TEX_R8] = {GL_R8, GL_RED, GL_UNSIGNED_BYTE},
    [DM_TEX_RG8] = {GL_RG8, GL_RG, GL_UNSIGNED_BYTE},
    [DM_TEX_RGBA8] = {GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE},
    [DM_TEX_RGBA8_SRGB] = {GL_SRGB8_ALPHA8, GL_RGBA, GL_UNSIGNED_BYTE},
    [DM_TEX_R16F] = {GL_R16F, GL_RED, GL_HALF_FLOAT},
    [DM_TEX_RG16F] = {GL_RG16F, GL_RG, GL_HALF_FLOAT},
    [DM_TEX_RGBA16F] = {GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT},
    [DM_TEX_R32F] = {GL_R32F, GL_RED, GL_FLOAT},
    [DM_TEX_RG32F] = {GL_RG32F, GL_RG, GL_FLOAT},
    [DM_TEX_RGBA32F] = {GL_RGBA32F, GL_RGBA, GL_FLOAT},
};

const char *dmr_format_name(dm_tex_format f)
{
    const dm_tex_format_info *i = dm_tex_format_get(f);
    return i ? i->name : "(invalid)";
}


/* ---- small matrix helpers (column-major, as GL takes them) ----------------------------- */

void dmr_mat_mul(float *o, const float *a, const float *b)
{
    float r[16];
    for (int c = 0; c < 4; ++c)
        for (int rr = 0; rr < 4; ++rr) {
            float s = 0;
            for (int k = 0; k < 4; ++k) s += a[k * 4 + rr] * b[c * 4 + k];
            r[c * 4 + rr] = s;
        }
    memcpy(o, r, sizeof r);
}

void dmr_v3_sub(float *o, const float *a, const float *b)
{
    for (int i = 0; i < 3; ++i) o[i] = a[i] - b[i];
}
float dmr_v3_dot(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
void dmr_v3_cross(float *o, const float *a, const float *b)
{
    float r[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    memcpy(o, r, sizeof r);
}
float dmr_v3_norm(float *v)
{
    float l = sqrtf(dmr_v3_dot(v, v));
    if (l > 0)
        for (int i = 0; i < 3; ++i) v[i] /= l;
    return l;
}

/* View matrix; also returns the camera basis (right, up, forward). */
void dmr_look_at(float *m, const float *eye, const float *target, const float *up_hint, float *right, float *up,
                    float *fwd)
{
    float f[3], s[3], u[3];
    dmr_v3_sub(f, target, eye);
    dmr_v3_norm(f);
    dmr_v3_cross(s, f, up_hint);
    if (dmr_v3_norm(s) < 1e-6f) { /* up parallel to the view: pick another */
        float alt[3] = {fabsf(f[0]) < 0.9f ? 1.0f : 0.0f, 0.0f, fabsf(f[0]) < 0.9f ? 0.0f : 1.0f};
        dmr_v3_cross(s, f, alt);
        dmr_v3_norm(s);
    }
    dmr_v3_cross(u, s, f);
    float r[16] = {s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
                   -dmr_v3_dot(s, eye), -dmr_v3_dot(u, eye), dmr_v3_dot(f, eye), 1};
    memcpy(m, r, sizeof r);
    if (right) memcpy(right, s, sizeof s);
    if (up) memcpy(up, u, sizeof u);
    if (fwd) memcpy(fwd, f, sizeof f);
}

void dmr_perspective(float *m, float fovy_rad, float aspect, float n, float f)
{
    float t = 1.0f / tanf(0.5f * fovy_rad);
    float r[16] = {t / aspect, 0, 0, 0, 0, t, 0, 0, 0, 0, (f + n) / (n - f), -1, 0, 0, 2 * f * n / (n - f), 0};
    memcpy(m, r, sizeof r);
}

void dmr_ortho(float *m, float half, float n, float f)
{
    float r[16] = {1 / half, 0, 0, 0, 0, 1 / half, 0, 0, 0, 0, -2 / (f - n), 0, 0, 0, -(f + n) / (f - n), 1};
    memcpy(m, r, sizeof r);
}
dm_result dmr_gl_check(const char *what, dm_error *err)
{
    GLenum e = glGetError(), first = e;
    while (e != GL_NO_ERROR) e = glGetError();
    if (first != GL_NO_ERROR) return dm_fail(err, DM_ERR_GL, "%s: GL error 0x%04x", what, (unsigned)first);
    return DM_OK;
}

/* ---- shaders -------------------------------------------------------------------------- */

static dm_result compile_stage(GLenum stage, const char *defines, const char *common, const char *src,
                               const char *name, GLuint *out, dm_error *err)
{
    const char *stage_define = stage == GL_VERTEX_SHADER ? "#define DM_VERTEX 1\n" : "#define DM_FRAGMENT 1\n";
    GLuint sh = glCreateShader(stage);
    /* "#line 1" before the pass keeps compiler messages in the pass file's numbering */
    const char *with_line[7] = {"#version 330 core\n", stage_define, defines, "#line 1 1\n", common,
                                "\n#line 1 2\n", src};
    glShaderSource(sh, 7, with_line, NULL);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[768] = "";
        glGetShaderInfoLog(sh, sizeof log, NULL, log);
        glDeleteShader(sh);
        return dm_fail(err, DM_ERR_GL, "%s (%s stage; source 1 = common.glsl, 2 = the pass): %s", name,
                       stage == GL_VERTEX_SHADER ? "vertex" : "fragment", log);
    }
    *out = sh;
    return DM_OK;
}

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
                 {"u_env_array", UNIT_ENV_ARRAY}, {"u_diffusion", UNIT_DIFFUSION}, {"u_aux", UNIT_SS_AUX}, {"u_glow", UNIT_GLOW},   {"u_spec", UNIT_SS_SPEC},
                 {"u_tdepth0", UNIT_TDEPTH0},     {"u_tdepth1", UNIT_TDEPTH0 + 1}, {"u_tdepth2", UNIT_TDEPTH0 + 2},
                 {"u_tdepth3", UNIT_TDEPTH0 + 3}, {"u_preint", UNIT_PREINT},   {"u_curvature", UNIT_CURVATURE}};
    glUseProgram(p);
    for (size_t i = 0; i < sizeof units / sizeof units[0]; ++i) {
        GLint loc = glGetUniformLocation(p, units[i].name);
        if (loc >= 0) glUniform1i(loc, units[i].unit);
    }
    char name[32];
    for (int i = 0; i < 4; ++i) {
        snprintf(name, sizeof name, "u_gbuf%d", i);
        GLint loc = glGetUniformLocation(p, name);
        if (loc >= 0) glUniform1i(loc, dmr_gbuffer_unit(p) + i);
    }
    for (int k = 0; k < DM_RENDER_ENV_LEVELS_MAX; ++k) {
        snprintf(name, sizeof name, "u_env_level[%d]", k);
        GLint loc = glGetUniformLocation(p, name);
        if (loc >= 0) glUniform1i(loc, UNIT_ENV_LEVEL0 + k);
    }
    for (int k = 0; k < DM_PROFILE_MAX_GAUSSIANS; ++k) { /* common.glsl's u_level[8] */
        snprintf(name, sizeof name, "u_level[%d]", k);
        GLint loc = glGetUniformLocation(p, name);
        if (loc >= 0) glUniform1i(loc, UNIT_LEVEL0 + k);
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
static size_t light_defines(const dm_renderer *r, char *out, size_t size)
{
    int shadow[DM_SCENE_MAX_LIGHTS + 1], point[DM_SCENE_MAX_LIGHTS + 1], light[DM_SCENE_MAX_LIGHTS + 1];
    int n = r->scene.light_count > 0 ? r->scene.light_count : 1, m = r->plan.shadow_count > 0 ? r->plan.shadow_count : 1;
    for (int i = 0; i < n; ++i) {
        shadow[i] = -1;
        point[i] = i < r->scene.light_count && r->scene.lights[i].type != DM_LIGHT_DIRECTIONAL;
    }
    for (int j = 0; j < r->plan.shadow_count; ++j) shadow[r->plan.shadow_light[j]] = j;
    for (int j = 0; j < m; ++j) light[j] = j < r->plan.shadow_count ? r->plan.shadow_light[j] : 0;
    size_t k = index_macro(out, size, "DM_LIGHT_SHADOW", shadow, n);
    k += index_macro(out + k, size - k, "DM_LIGHT_POINT", point, n);
    k += index_macro(out + k, size - k, "DM_SHADOW_LIGHT", light, m);
    if (r->has_normal_map) k += (size_t)snprintf(out + k, size - k, "#define DM_NORMAL_MAP 1\n");
    if (r->has_roughness_map && k < size) k += (size_t)snprintf(out + k, size - k, "#define DM_ROUGHNESS_MAP 1\n");
    return k < size ? k : size - 1;
}

dm_result dmr_build_program(dm_renderer *r, const char *file, const char *extra, GLuint *out, dm_error *err)
{
    char defines[2048];
    const dm_render_plan *p = &r->plan;
    snprintf(defines, sizeof defines,
             "%s%s%s%s#define DM_LIGHTS %d\n#define DM_SHADOW_MAPS %d\n#define DM_TAPS %d\n#define DM_LEVELS %d\n#define DM_ENV_LEVELS %d\n"
             "#define DM_SHADOW_TAPS %d\n%s",
             p->texture_space ? "#define DM_SUBSURFACE 1\n" : "",
             p->effects[DM_EFFECT_SPECULAR] ? "#define DM_SPECULAR 1\n" : "",
             p->energy_conservation_active ? "#define DM_ENERGY 1\n" : "",
             p->effects[DM_EFFECT_ENVIRONMENT_LIGHTING] ? "#define DM_ENV 1\n" : "", r->scene.light_count,
             p->shadow_count, r->taps, p->texture_space ? r->profile.count : 0, r->env_level_count,
             r->shadow_taps, r->tex_env_array ? "#define DM_ENV_ARRAY 1\n" : "");
    size_t n = strlen(defines);
    n += light_defines(r, defines + n, sizeof defines - n);
    /* appended only when on */
    if (p->screen_space)
        n += (size_t)snprintf(defines + n, sizeof defines - n, "#define DM_SCREEN_SPACE 1\n#define DM_SS_TAPS %d\n",
                              r->ss_taps);
    if (p->pre_integrated) n += (size_t)snprintf(defines + n, sizeof defines - n, "#define DM_PRE_INTEGRATED 1\n");
    if (p->translucency_active)
        n += (size_t)snprintf(defines + n, sizeof defines - n,
                              "#define DM_TRANSLUCENCY 1\n#define DM_TRANS_GAUSSIANS %d\n", r->profile.count);
    if (p->glow_in_tonemap) n += (size_t)snprintf(defines + n, sizeof defines - n, "#define DM_GLOW 1\n");
    if (r->spec_in_normal) n += (size_t)snprintf(defines + n, sizeof defines - n, "#define DM_SPEC_IN_NORMAL 1\n");
    if (r->diffusion_sum) n += (size_t)snprintf(defines + n, sizeof defines - n, "#define DM_DIFFUSION_SUM 1\n");
    if (extra) snprintf(defines + n, sizeof defines - n, "%s", extra);
    const char *dir = r->shader_dir[0] ? r->shader_dir : NULL;
    char *common = NULL, *src = NULL;
    dm_result rc = dm_render_shader_source(dir, "common.glsl", &common, err);
    if (rc == DM_OK) rc = dm_render_shader_source(dir, file, &src, err);
    /* a pass file without a vertex stage takes common.glsl's full-screen triangle */
    if (rc == DM_OK && !strstr(src, "DM_VERTEX"))
        snprintf(defines + strlen(defines), sizeof defines - strlen(defines), "#define DM_FULLSCREEN 1\n");
    /* one that rasterises the mesh takes common.glsl's attributes and varyings for it */
    else if (rc == DM_OK && strstr(src, "dm_mesh_vertex(") && !strstr(defines, "DM_FULLSCREEN"))
        snprintf(defines + strlen(defines), sizeof defines - strlen(defines), "#define DM_MESH_VERTEX 1\n");
    GLuint vs = 0, fs = 0;
    if (rc == DM_OK) rc = compile_stage(GL_VERTEX_SHADER, defines, common, src, file, &vs, err);
    if (rc == DM_OK) rc = compile_stage(GL_FRAGMENT_SHADER, defines, common, src, file, &fs, err);
    free(common);
    free(src);
    if (rc != DM_OK) {
        if (vs) glDeleteShader(vs);
        return rc;
    }
    GLuint prog = glCreateProgram();
    glAttachShader(prog, vs);
    glAttachShader(prog, fs);
    glBindAttribLocation(prog, 0, "a_position");
    glBindAttribLocation(prog, 1, "a_normal");
    glBindAttribLocation(prog, 2, "a_tangent");
    glBindAttribLocation(prog, 3, "a_uv");
    glLinkProgram(prog);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[768] = "";
        glGetProgramInfoLog(prog, sizeof log, NULL, log);
        glDeleteProgram(prog);
        return dm_fail(err, DM_ERR_GL, "%s: link failed: %s", file, log);
    }
    set_sampler_units(prog);
    *out = prog;
    return dmr_gl_check(file, err);
}
/* ---- uploads and targets -------------------------------------------------------------- */

dm_result dmr_upload(const dm_texture *t, const char *what, bool mipmaps, GLenum filter, GLuint *out,
                        dm_error *err)
{
    if (!dm_tex_format_get(t->format))
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: texture format %d is not a dm_tex_format", what,
                       (int)t->format);
    if (t->width < 1 || t->height < 1 || t->width > 16384 || t->height > 16384)
        return dm_fail(err, DM_ERR_RANGE, "%s: size %dx%d, expected 1..16384 per side", what, t->width, t->height);
    const fmt_gl *f = &dmr_formats[t->format];
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, (GLint)f->internal, t->width, t->height, 0, f->format, f->type, t->texels);
    if (mipmaps) glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                    mipmaps ? GL_LINEAR_MIPMAP_LINEAR : (GLint)filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, (GLint)filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    *out = tex;
    return dmr_gl_check(what, err);
}

GLuint dmr_solid_texture(uint8_t v)
{
    uint8_t px[4] = {v, v, v, 255};
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, px);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return tex;
}
