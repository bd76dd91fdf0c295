#include "render/dm_render.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "core/dm_cli.h"
#include "core/dm_math.h"
#include "render/dm_render_shaders.h"

/* ---- texture formats ------------------------------------------------------------------ */

/* The GL side of each pack format (core/dm_pack.h owns names and sizes). */
typedef struct fmt_gl {
    GLenum internal, format, type;
} fmt_gl;

static const fmt_gl formats[DM_TEX_FORMAT_COUNT] = {
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

static const char *format_name(dm_tex_format f)
{
    const dm_tex_format_info *i = dm_tex_format_get(f);
    return i ? i->name : "(invalid)";
}


/* ---- the blur kernel ------------------------------------------------------------------ */

static double phi(double x) /* standard normal CDF */
{
    return 0.5 * erfc(-x / sqrt(2.0));
}

double dm_render_blur_kernel(int taps, float *offsets_sigma, float *weights)
{
    assert(taps >= 3 && taps <= 63 && taps % 2 == 1);
    int h = (taps - 1) / 2;
    double step = 3.0 / h, var = 0.0;
    for (int i = 0; i < taps; ++i) {
        double x = (i - h) * step;
        double lo = i == 0 ? -INFINITY : x - 0.5 * step, hi = i == taps - 1 ? INFINITY : x + 0.5 * step;
        double w = (isinf(hi) ? 1.0 : phi(hi)) - (isinf(lo) ? 0.0 : phi(lo));
        offsets_sigma[i] = (float)x;
        weights[i] = (float)w;
        var += w * x * x;
    }
    return var;
}

/* ---- small matrix helpers (column-major, as GL takes them) ----------------------------- */

static void mat_mul(float *o, const float *a, const float *b)
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

static void v3_sub(float *o, const float *a, const float *b)
{
    for (int i = 0; i < 3; ++i) o[i] = a[i] - b[i];
}
static float v3_dot(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static void v3_cross(float *o, const float *a, const float *b)
{
    float r[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    memcpy(o, r, sizeof r);
}
static float v3_norm(float *v)
{
    float l = sqrtf(v3_dot(v, v));
    if (l > 0)
        for (int i = 0; i < 3; ++i) v[i] /= l;
    return l;
}

/* View matrix; also returns the camera basis (right, up, forward). */
static void look_at(float *m, const float *eye, const float *target, const float *up_hint, float *right, float *up,
                    float *fwd)
{
    float f[3], s[3], u[3];
    v3_sub(f, target, eye);
    v3_norm(f);
    v3_cross(s, f, up_hint);
    if (v3_norm(s) < 1e-6f) { /* up parallel to the view: pick another */
        float alt[3] = {fabsf(f[0]) < 0.9f ? 1.0f : 0.0f, 0.0f, fabsf(f[0]) < 0.9f ? 0.0f : 1.0f};
        v3_cross(s, f, alt);
        v3_norm(s);
    }
    v3_cross(u, s, f);
    float r[16] = {s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
                   -v3_dot(s, eye), -v3_dot(u, eye), v3_dot(f, eye), 1};
    memcpy(m, r, sizeof r);
    if (right) memcpy(right, s, sizeof s);
    if (up) memcpy(up, u, sizeof u);
    if (fwd) memcpy(fwd, f, sizeof f);
}

static void perspective(float *m, float fovy_rad, float aspect, float n, float f)
{
    float t = 1.0f / tanf(0.5f * fovy_rad);
    float r[16] = {t / aspect, 0, 0, 0, 0, t, 0, 0, 0, 0, (f + n) / (n - f), -1, 0, 0, 2 * f * n / (n - f), 0};
    memcpy(m, r, sizeof r);
}

static void ortho(float *m, float half, float n, float f)
{
    float r[16] = {1 / half, 0, 0, 0, 0, 1 / half, 0, 0, 0, 0, -2 / (f - n), 0, 0, 0, -(f + n) / (f - n), 1};
    memcpy(m, r, sizeof r);
}

/* ---- the renderer --------------------------------------------------------------------- */

enum {
    UNIT_ALBEDO = 0,
    UNIT_NORMAL,
    UNIT_SPECULAR,
    UNIT_ROUGHNESS,
    UNIT_BECKMANN,
    UNIT_RHO_DT,
    UNIT_ENV_BRDF,
    UNIT_SHADOW, /* DM_PLAN_MAX_SHADOWS units */
    UNIT_SHADOW_END = UNIT_SHADOW + DM_PLAN_MAX_SHADOWS - 1,
    UNIT_ENV_LEVEL0, /* 6 */
    UNIT_LEVEL0 = UNIT_ENV_LEVEL0 + DM_RENDER_ENV_LEVELS_MAX, /* 8 */
    UNIT_SRC = UNIT_LEVEL0 + 8,
    UNIT_STRETCH,
    UNIT_MASK,
    UNIT_DEPTH,
    UNIT_BACKGROUND,
    UNIT_ENV_ARRAY,
    UNIT_COUNT
};

typedef struct target {
    char name[32];
    GLuint fbo;
    int width, height, channels; /* channels 1: depth */
} target;

enum { MAX_TARGETS = 32 };

struct dm_renderer {
    dm_scene scene;
    dm_profile profile;
    dm_render_desc desc;
    char shader_dir[4096];
    int width, height, irr_size, shadow_size, taps;
    int shadow_taps;                            /* 1, 4 or 9 (DM_SHADOW_TAPS) */
    int level_size[DM_PROFILE_MAX_GAUSSIANS];   /* texels per side of each irradiance level */
    GLenum level_format;                        /* GL_RGBA32F or GL_RGBA16F */
    bool ts_valid;                              /* texture-space results reusable (reuse_texture_space) */
    int ts_pass_count;                          /* shadow + irradiance + blur passes of the final plan */
    float ts_rotation;                          /* the light rotation they were made with, */
    float ts_blur_scale, ts_roughness_scale;    /* and the per-frame scales */
    int stretch_count, env_level_count;
    float env_level_m[DM_RENDER_ENV_LEVELS_MAX];
    float env_sh[DM_RENDER_SH_COUNT][3];
    bool has_normal_map, has_roughness_map, has_mask;
    float center[3], radius;
    float blur_offset[DM_PROFILE_MAX_GAUSSIANS][63]; /* mm, per level k (index k) */
    float blur_weight[63];
    float blur_scale; /* variance scale the blur offsets were made for (1 at create) */
    float level_weight[DM_PROFILE_MAX_GAUSSIANS][3];

    dm_render_plan plan;
    bool tonemapped; /* the last frame's display came from the tonemap pass */

    GLuint vao_mesh, vbo, ebo, vao_empty;
    int index_count;
    GLuint tex_albedo, tex_normal, tex_spec, tex_rough, tex_beckmann, tex_rho_dt, tex_env_brdf;
    GLuint tex_stretch[DM_PROFILE_MAX_GAUSSIANS], tex_mask, tex_env_level[DM_RENDER_ENV_LEVELS_MAX],
        tex_background;
    GLuint tex_white, tex_black;
    GLuint tex_env_array; /* the env levels as one 2D array when they share size and format */
    GLuint shadow_tex[DM_PLAN_MAX_SHADOWS], shadow_fbo[DM_PLAN_MAX_SHADOWS];
    GLuint irr_tex[DM_PROFILE_MAX_GAUSSIANS], irr_fbo[DM_PROFILE_MAX_GAUSSIANS], tmp_tex, tmp_fbo;
    GLuint tmp_small_tex, tmp_small_fbo; /* the U pass target of the reduced levels */
    GLuint screen_tex, screen_depth, screen_fbo;
    GLuint view_tex, view_fbo; /* texture views at their own size, RGBA32F (resized on demand) */
    int view_target;           /* its index in targets */
    bool view_in_target;       /* the last frame was a texture view: read_view reads "view" */
    GLuint glow_tex[2], glow_fbo[2];
    GLuint display_tex, display_fbo;
    GLuint prog[DM_PASS_KIND_COUNT];
    GLuint prog_glow_blur; /* shared by both glow blur passes */

    target targets[MAX_TARGETS];
    int target_count;

    /* per-frame light state */
    float light_pos[DM_SCENE_MAX_LIGHTS][4], light_color[DM_SCENE_MAX_LIGHTS][3];
    int light_shadow[DM_SCENE_MAX_LIGHTS];
    float light_matrix[DM_SCENE_MAX_LIGHTS][16];
    float view_proj[16], eye[3], cam_right[3], cam_up[3], cam_fwd[3];

    bool timing_cpu;
    GLuint queries[DM_PLAN_MAX_PASSES];
    double pass_ms[DM_PLAN_MAX_PASSES], frame_ms;
    char gl_name[256];
    float roughness_scale; /* of the current frame */
};

static const char *pass_shader[DM_PASS_KIND_COUNT] = {
    [DM_PASS_SHADOW] = "shadow.glsl",           [DM_PASS_IRRADIANCE] = "irradiance.glsl",
    [DM_PASS_BLUR_U] = "blur.glsl",             [DM_PASS_BLUR_V] = "blur.glsl",
    [DM_PASS_FINAL] = "final.glsl",             [DM_PASS_BACKGROUND] = "background.glsl",
    [DM_PASS_GLOW_BRIGHT] = "glow_bright.glsl", [DM_PASS_GLOW_BLUR_U] = "glow_blur.glsl",
    [DM_PASS_GLOW_BLUR_V] = "glow_blur.glsl",   [DM_PASS_GLOW_ADD] = "glow_add.glsl",
    [DM_PASS_TONEMAP] = "tonemap.glsl",         [DM_PASS_VIEW] = "view.glsl",
};

static dm_result gl_check(const char *what, dm_error *err)
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
                 {"u_env_array", UNIT_ENV_ARRAY}};
    glUseProgram(p);
    for (size_t i = 0; i < sizeof units / sizeof units[0]; ++i) {
        GLint loc = glGetUniformLocation(p, units[i].name);
        if (loc >= 0) glUniform1i(loc, units[i].unit);
    }
    char name[32];
    for (int k = 0; k < DM_RENDER_ENV_LEVELS_MAX; ++k) {
        snprintf(name, sizeof name, "u_env_level[%d]", k);
        GLint loc = glGetUniformLocation(p, name);
        if (loc >= 0) glUniform1i(loc, UNIT_ENV_LEVEL0 + k);
    }
    for (int k = 0; k < 8; ++k) {
        snprintf(name, sizeof name, "u_level[%d]", k);
        GLint loc = glGetUniformLocation(p, name);
        if (loc >= 0) glUniform1i(loc, UNIT_LEVEL0 + k);
    }
}

static dm_result build_program(dm_renderer *r, const char *file, GLuint *out, dm_error *err)
{
    char defines[512];
    const dm_render_plan *p = &r->plan;
    snprintf(defines, sizeof defines,
             "%s%s%s%s#define DM_LIGHTS %d\n#define DM_SHADOW_MAPS %d\n#define DM_TAPS %d\n#define DM_LEVELS %d\n#define DM_ENV_LEVELS %d\n"
             "#define DM_SHADOW_TAPS %d\n%s",
             p->effects[DM_EFFECT_SUBSURFACE] ? "#define DM_SUBSURFACE 1\n" : "",
             p->effects[DM_EFFECT_SPECULAR] ? "#define DM_SPECULAR 1\n" : "",
             p->energy_conservation_active ? "#define DM_ENERGY 1\n" : "",
             p->effects[DM_EFFECT_ENVIRONMENT_LIGHTING] ? "#define DM_ENV 1\n" : "", r->scene.light_count,
             p->shadow_count, r->taps, p->effects[DM_EFFECT_SUBSURFACE] ? r->profile.count : 0, r->env_level_count,
             r->shadow_taps, r->tex_env_array ? "#define DM_ENV_ARRAY 1\n" : "");
    const char *dir = r->shader_dir[0] ? r->shader_dir : NULL;
    char *common = NULL, *src = NULL;
    dm_result rc = dm_render_shader_source(dir, "common.glsl", &common, err);
    if (rc == DM_OK) rc = dm_render_shader_source(dir, file, &src, err);
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
    return gl_check(file, err);
}

/* ---- uniforms ------------------------------------------------------------------------- */

static GLint loc(GLuint p, const char *name)
{
    return glGetUniformLocation(p, name);
}
static void u1i(GLuint p, const char *n, int v)
{
    glUniform1i(loc(p, n), v);
}
static void u1f(GLuint p, const char *n, float v)
{
    glUniform1f(loc(p, n), v);
}
static void u2f(GLuint p, const char *n, float a, float b)
{
    glUniform2f(loc(p, n), a, b);
}

/* ---- uploads and targets -------------------------------------------------------------- */

static dm_result upload(const dm_texture *t, const char *what, bool mipmaps, GLenum filter, GLuint *out,
                        dm_error *err)
{
    if (!dm_tex_format_get(t->format))
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: texture format %d is not a dm_tex_format", what,
                       (int)t->format);
    if (t->width < 1 || t->height < 1 || t->width > 16384 || t->height > 16384)
        return dm_fail(err, DM_ERR_RANGE, "%s: size %dx%d, expected 1..16384 per side", what, t->width, t->height);
    const fmt_gl *f = &formats[t->format];
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
    return gl_check(what, err);
}

static GLuint solid_texture(uint8_t v)
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

static void add_target(dm_renderer *r, const char *name, GLuint fbo, int w, int h, int channels)
{
    assert(r->target_count < MAX_TARGETS);
    target *t = &r->targets[r->target_count++];
    snprintf(t->name, sizeof t->name, "%s", name);
    t->fbo = fbo;
    t->width = w;
    t->height = h;
    t->channels = channels;
}

static dm_result color_target(dm_renderer *r, const char *name, int w, int h, GLenum internal, GLenum wrap,
                              GLuint *tex, GLuint *fbo, dm_error *err)
{
    glGenTextures(1, tex);
    glBindTexture(GL_TEXTURE_2D, *tex);
    glTexImage2D(GL_TEXTURE_2D, 0, (GLint)internal, w, h, 0, GL_RGBA, GL_FLOAT, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, (GLint)wrap);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, (GLint)wrap);
    const float border[4] = {0, 0, 0, 0};
    glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, border);
    glGenFramebuffers(1, fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, *fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, *tex, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return dm_fail(err, DM_ERR_GL, "target %s (%dx%d): framebuffer incomplete", name, w, h);
    add_target(r, name, *fbo, w, h, 4);
    return gl_check(name, err);
}

static dm_result make_targets(dm_renderer *r, dm_error *err)
{
    dm_result rc = DM_OK;
    const dm_render_plan *p = &r->plan;
    char name[32];
    if (p->shadow_count > 0) {
        /* separate 2D depth textures, not one array: llvmpipe's sampler2DArrayShadow path
         * measured ~4x slower per tap than sampler2DShadow */
        for (int i = 0; i < p->shadow_count; ++i) {
            glGenTextures(1, &r->shadow_tex[i]);
            glBindTexture(GL_TEXTURE_2D, r->shadow_tex[i]);
            glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, r->shadow_size, r->shadow_size, 0,
                         GL_DEPTH_COMPONENT, GL_FLOAT, NULL);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
            glGenFramebuffers(1, &r->shadow_fbo[i]);
            glBindFramebuffer(GL_FRAMEBUFFER, r->shadow_fbo[i]);
            glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, r->shadow_tex[i], 0);
            glDrawBuffer(GL_NONE);
            glReadBuffer(GL_NONE);
            snprintf(name, sizeof name, "shadow%d", i);
            if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
                return dm_fail(err, DM_ERR_GL, "target %s: framebuffer incomplete", name);
            add_target(r, name, r->shadow_fbo[i], r->shadow_size, r->shadow_size, 1);
        }
    }
    if (p->effects[DM_EFFECT_SUBSURFACE]) {
        for (int k = 0; k < p->blur_levels && rc == DM_OK; ++k) {
            snprintf(name, sizeof name, k == 0 ? "irradiance" : "blur%d", k);
            rc = color_target(r, name, r->level_size[k], r->level_size[k], r->level_format, GL_CLAMP_TO_BORDER,
                              &r->irr_tex[k], &r->irr_fbo[k], err);
        }
        if (rc == DM_OK && p->blur_levels > 1)
            rc = color_target(r, "blur_tmp", r->irr_size, r->irr_size, r->level_format, GL_CLAMP_TO_BORDER,
                              &r->tmp_tex, &r->tmp_fbo, err);
        int small = r->level_size[p->blur_levels > 0 ? p->blur_levels - 1 : 0];
        if (rc == DM_OK && p->blur_levels > 1 && small != r->irr_size)
            rc = color_target(r, "blur_tmp_small", small, small, r->level_format, GL_CLAMP_TO_BORDER,
                              &r->tmp_small_tex, &r->tmp_small_fbo, err);
    }
    if (rc != DM_OK) return rc;
    /* float32: read_linear and read_view return it at full precision (alpha = coverage) */
    rc = color_target(r, "screen", r->width, r->height, GL_RGBA32F, GL_CLAMP_TO_EDGE, &r->screen_tex, &r->screen_fbo,
                      err);
    if (rc != DM_OK) return rc;
    r->view_target = r->target_count;
    rc = color_target(r, "view", 1, 1, GL_RGBA32F, GL_CLAMP_TO_EDGE, &r->view_tex, &r->view_fbo, err);
    if (rc != DM_OK) return rc;
    glGenRenderbuffers(1, &r->screen_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, r->screen_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, r->width, r->height);
    glBindFramebuffer(GL_FRAMEBUFFER, r->screen_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->screen_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return dm_fail(err, DM_ERR_GL, "target screen: framebuffer with depth incomplete");
    if (p->effects[DM_EFFECT_GLOW]) {
        int gw = r->width / 2 > 0 ? r->width / 2 : 1, gh = r->height / 2 > 0 ? r->height / 2 : 1;
        rc = color_target(r, "glow_a", gw, gh, GL_RGBA16F, GL_CLAMP_TO_EDGE, &r->glow_tex[0], &r->glow_fbo[0], err);
        if (rc == DM_OK)
            rc = color_target(r, "glow_b", gw, gh, GL_RGBA16F, GL_CLAMP_TO_EDGE, &r->glow_tex[1], &r->glow_fbo[1],
                              err);
    }
    if (rc == DM_OK && p->effects[DM_EFFECT_TONEMAP])
        rc = color_target(r, "display", r->width, r->height, GL_RGBA8, GL_CLAMP_TO_EDGE, &r->display_tex,
                          &r->display_fbo, err);
    return rc;
}

/* ---- asset checks --------------------------------------------------------------------- */

static dm_result need_texture(const dm_texture *t, const char *what, const char *effect, dm_error *err)
{
    if (!t->texels)
        return dm_fail(err, DM_ERR_MISMATCH, "assets: %s is missing, and the %s effect needs it", what, effect);
    return DM_OK;
}

static dm_result check_assets(const dm_render_assets *a, const dm_render_plan *p, const dm_profile *prof,
                              dm_error *err)
{
    if (!a->vertices || a->vertex_count < 3 || !a->indices || a->index_count < 3 || a->index_count % 3)
        return dm_fail(err, DM_ERR_EMPTY, "assets: mesh has %d vertices and %d indices, expected >= 3 and a multiple of 3",
                       a->vertex_count, a->index_count);
    for (int i = 0; i < a->index_count; ++i)
        if (a->indices[i] >= (uint32_t)a->vertex_count)
            return dm_fail(err, DM_ERR_RANGE, "assets: index %d is %u, expected < vertex_count %d", i,
                           (unsigned)a->indices[i], a->vertex_count);
    dm_result rc = DM_OK;
    if (p->effects[DM_EFFECT_SPECULAR]) rc = need_texture(&a->beckmann, "the Beckmann LUT", "specular", err);
    if (rc == DM_OK && p->energy_conservation_active)
        rc = need_texture(&a->rho_dt, "the rho_dt LUT", "energy_conservation", err);
    if (rc == DM_OK && p->effects[DM_EFFECT_ENVIRONMENT_LIGHTING] && !a->has_env_sh)
        rc = dm_fail(err, DM_ERR_MISMATCH, "assets: the environment SH is missing, and environment_lighting needs it");
    if (rc == DM_OK && p->env_specular_active) {
        if (a->env_level_count < 1 || a->env_level_count > DM_RENDER_ENV_LEVELS_MAX)
            return dm_fail(err, DM_ERR_MISMATCH,
                           "assets: %d prefiltered environment levels, environment_lighting with specular needs 1..%d",
                           a->env_level_count, DM_RENDER_ENV_LEVELS_MAX);
        for (int k = 0; k < a->env_level_count && rc == DM_OK; ++k) {
            rc = need_texture(&a->env_levels[k], "a prefiltered environment level", "environment_lighting", err);
            if (rc == DM_OK && k > 0 && !(a->env_level_m[k] > a->env_level_m[k - 1]))
                rc = dm_fail(err, DM_ERR_RANGE, "assets: env_level_m[%d] = %g, expected more than env_level_m[%d] = %g",
                             k, (double)a->env_level_m[k], k - 1, (double)a->env_level_m[k - 1]);
        }
        if (rc == DM_OK) rc = need_texture(&a->env_brdf, "the env-BRDF LUT", "environment_lighting", err);
    }
    if (rc == DM_OK && dm_render_plan_find(p, "background") >= 0)
        rc = need_texture(&a->env_background, "the environment background", "environment_lighting", err);
    if (rc == DM_OK && p->effects[DM_EFFECT_SUBSURFACE]) {
        rc = dm_profile_validate(prof, "assets: profile", err);
        if (rc == DM_OK && (a->stretch_level_count < 1 || a->stretch_level_count > DM_PROFILE_MAX_GAUSSIANS))
            return dm_fail(err, DM_ERR_MISMATCH, "assets: %d stretch levels, subsurface needs 1..%d",
                           a->stretch_level_count, DM_PROFILE_MAX_GAUSSIANS);
        for (int k = 0; k < a->stretch_level_count && rc == DM_OK; ++k) {
            rc = need_texture(&a->stretch[k], "a stretch level", "subsurface", err);
            if (rc == DM_OK && a->stretch[k].format != DM_TEX_RG32F && a->stretch[k].format != DM_TEX_RG16F)
                rc = dm_fail(err, DM_ERR_UNSUPPORTED, "assets: stretch level %d is %s, expected rg32f or rg16f", k,
                             format_name(a->stretch[k].format));
        }
        int taps = a->scene->blur_taps;
        if (rc == DM_OK && (taps < 3 || taps > 63 || taps % 2 == 0))
            rc = dm_fail(err, DM_ERR_RANGE, "scene: blur_taps = %d, expected an odd integer in [3, 63]", taps);
    }
    return rc;
}

/* ---- create / destroy ----------------------------------------------------------------- */

static void mesh_bounds(dm_renderer *r, const float *v, int n)
{
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            float x = v[(size_t)i * DM_VERTEX_FLOATS + c];
            lo[c] = fminf(lo[c], x);
            hi[c] = fmaxf(hi[c], x);
        }
    float rad = 0;
    for (int c = 0; c < 3; ++c) r->center[c] = 0.5f * (lo[c] + hi[c]);
    for (int i = 0; i < n; ++i) {
        float d[3];
        v3_sub(d, &v[(size_t)i * DM_VERTEX_FLOATS], r->center);
        rad = fmaxf(rad, v3_dot(d, d));
    }
    r->radius = sqrtf(rad) > 1e-6f ? sqrtf(rad) : 1.0f;
}

static dm_result upload_env_array(dm_renderer *r, const dm_render_assets *a, dm_error *err);

static dm_result upload_assets(dm_renderer *r, const dm_render_assets *a, dm_error *err)
{
    glGenVertexArrays(1, &r->vao_mesh);
    glBindVertexArray(r->vao_mesh);
    glGenBuffers(1, &r->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)a->vertex_count * DM_VERTEX_STRIDE, a->vertices, GL_STATIC_DRAW);
    glGenBuffers(1, &r->ebo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)a->index_count * 4, a->indices, GL_STATIC_DRAW);
    const int offs[4] = {DM_VERTEX_POSITION, DM_VERTEX_NORMAL, DM_VERTEX_TANGENT, DM_VERTEX_UV};
    const int sizes[4] = {3, 3, 4, 2};
    for (int i = 0; i < 4; ++i) {
        glEnableVertexAttribArray((GLuint)i);
        glVertexAttribPointer((GLuint)i, sizes[i], GL_FLOAT, GL_FALSE, DM_VERTEX_STRIDE,
                              (const void *)(size_t)(offs[i] * 4));
    }
    glBindVertexArray(0);
    glGenVertexArrays(1, &r->vao_empty);
    r->index_count = a->index_count;
    mesh_bounds(r, a->vertices, a->vertex_count);

    r->tex_white = solid_texture(255);
    r->tex_black = solid_texture(0);
    dm_result rc = DM_OK;
#define UP(field, what, mips, filt, dst)                                                                          \
    if (rc == DM_OK && a->field.texels) rc = upload(&a->field, what, mips, filt, &r->dst, err)
    UP(albedo, "albedo", true, GL_LINEAR, tex_albedo);
    UP(normal_map, "normal_map", true, GL_LINEAR, tex_normal);
    UP(specular_map, "specular_map", true, GL_LINEAR, tex_spec);
    UP(roughness_map, "roughness_map", true, GL_LINEAR, tex_rough);
    const dm_render_plan *p = &r->plan;
    if (p->effects[DM_EFFECT_SPECULAR]) UP(beckmann, "beckmann", false, GL_LINEAR, tex_beckmann);
    if (p->energy_conservation_active) UP(rho_dt, "rho_dt", false, GL_LINEAR, tex_rho_dt);
    if (p->env_specular_active) {
        UP(env_brdf, "env_brdf", false, GL_LINEAR, tex_env_brdf);
        for (int k = 0; k < a->env_level_count && rc == DM_OK; ++k) {
            rc = upload(&a->env_levels[k], "env_levels", false, GL_LINEAR, &r->tex_env_level[k], err);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
        }
        r->env_level_count = a->env_level_count;
        memcpy(r->env_level_m, a->env_level_m, sizeof r->env_level_m);
        if (rc == DM_OK) rc = upload_env_array(r, a, err);
    }
    if (dm_render_plan_find(p, "background") >= 0) {
        UP(env_background, "env_background", false, GL_LINEAR, tex_background);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    }
    if (p->effects[DM_EFFECT_SUBSURFACE]) {
        r->stretch_count = a->stretch_level_count;
        for (int k = 0; k < a->stretch_level_count && rc == DM_OK; ++k)
            rc = upload(&a->stretch[k], "stretch", false, GL_LINEAR, &r->tex_stretch[k], err);
        UP(stretch_mask, "stretch_mask", false, GL_LINEAR, tex_mask);
    }
#undef UP
    r->has_normal_map = a->normal_map.texels != NULL;
    r->has_roughness_map = a->roughness_map.texels != NULL;
    r->has_mask = a->stretch_mask.texels != NULL;
    if (a->has_env_sh) memcpy(r->env_sh, a->env_sh, sizeof r->env_sh);
    if (rc != DM_OK) return rc;
    return gl_check("upload", err);
}

/* The env levels again as one 2D array texture (two fetches per pixel instead of a chain of
 * branches that llvmpipe runs in full), when they share size and format, as a pack's do. */
static dm_result upload_env_array(dm_renderer *r, const dm_render_assets *a, dm_error *err)
{
    const dm_texture *t0 = &a->env_levels[0];
    for (int k = 1; k < a->env_level_count; ++k)
        if (a->env_levels[k].width != t0->width || a->env_levels[k].height != t0->height ||
            a->env_levels[k].format != t0->format)
            return DM_OK; /* the per-level path stays */
    const fmt_gl *f = &formats[t0->format];
    glGenTextures(1, &r->tex_env_array);
    glBindTexture(GL_TEXTURE_2D_ARRAY, r->tex_env_array);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, (GLint)f->internal, t0->width, t0->height, a->env_level_count, 0, f->format,
                 f->type, NULL);
    for (int k = 0; k < a->env_level_count; ++k)
        glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, k, t0->width, t0->height, 1, f->format, f->type,
                        a->env_levels[k].texels);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return gl_check("env_levels (array)", err);
}

static void prepare_blur(dm_renderer *r, float scale)
{
    float off_sigma[63];
    double var = dm_render_blur_kernel(r->taps, off_sigma, r->blur_weight);
    r->blur_scale = scale;
    for (int k = 1; k < r->profile.count; ++k) {
        double dv = (r->profile.variance_mm2[k] - r->profile.variance_mm2[k - 1]) * (double)scale;
        /* scale so that the discrete kernel's variance is exactly dv */
        double s = sqrt(dv / var);
        for (int i = 0; i < r->taps; ++i) r->blur_offset[k][i] = (float)(off_sigma[i] * s);
    }
    for (int c = 0; c < 3; ++c) {
        double sum = 0;
        for (int k = 0; k < r->profile.count; ++k) sum += r->profile.weight[k][c];
        for (int k = 0; k < r->profile.count; ++k)
            r->level_weight[k][c] = sum > 0 ? (float)(r->profile.weight[k][c] / sum) : 0.0f;
    }
}

dm_result dm_renderer_create(const dm_render_assets *a, const dm_render_desc *desc, dm_renderer **out,
                             dm_error *err)
{
    assert(a && a->scene && desc && out);
    *out = NULL;
    dm_renderer *r = calloc(1, sizeof *r);
    if (!r) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "renderer: cannot allocate");
    r->scene = *a->scene;
    r->profile = a->profile ? *a->profile : a->scene->profile;
    r->desc = *desc;
    if (desc->shader_dir) snprintf(r->shader_dir, sizeof r->shader_dir, "%s", desc->shader_dir);
    r->desc.shader_dir = NULL;
    r->width = desc->width > 0 ? desc->width : a->scene->width;
    r->height = desc->height > 0 ? desc->height : a->scene->height;
    r->irr_size = desc->irradiance_size > 0 ? desc->irradiance_size : a->scene->irradiance_size;
    r->shadow_size = desc->shadow_size > 0 ? desc->shadow_size : 1024;
    r->taps = a->scene->blur_taps;
    r->scene.profile = r->profile;
    r->shadow_taps = desc->shadow_pcf_taps > 0 ? desc->shadow_pcf_taps : 4;
    r->level_format = desc->blur_half_float ? GL_RGBA16F : GL_RGBA32F;
    int shift = desc->blur_reduce_shift > 0 ? desc->blur_reduce_shift : 1;
    for (int k = 0; k < DM_PROFILE_MAX_GAUSSIANS; ++k) {
        bool reduced = desc->blur_reduce_from > 0 && k >= desc->blur_reduce_from;
        r->level_size[k] = reduced ? r->irr_size >> shift : r->irr_size;
    }

    dm_result rc = DM_OK;
    if (r->width < 1 || r->height < 1 || r->width > 16384 || r->height > 16384)
        rc = dm_fail(err, DM_ERR_RANGE, "renderer: output size %dx%d, expected 1..16384 per side", r->width,
                     r->height);
    else if (a->scene->effects[DM_EFFECT_SUBSURFACE] && (r->irr_size < 8 || r->irr_size > 8192))
        rc = dm_fail(err, DM_ERR_RANGE, "renderer: irradiance size %d, expected 8..8192", r->irr_size);
    else if (r->shadow_size < 16 || r->shadow_size > 8192)
        rc = dm_fail(err, DM_ERR_RANGE, "renderer: shadow size %d, expected 16..8192", r->shadow_size);
    else if (r->shadow_taps != 1 && r->shadow_taps != 4 && r->shadow_taps != 9)
        rc = dm_fail(err, DM_ERR_RANGE, "renderer: shadow_pcf_taps %d, expected 0 (4), 1, 4 or 9", r->shadow_taps);
    else if (desc->blur_reduce_from < 0 || desc->blur_reduce_from >= DM_PROFILE_MAX_GAUSSIANS)
        rc = dm_fail(err, DM_ERR_RANGE, "renderer: blur_reduce_from %d, expected 0 (off) or a level 1..%d",
                     desc->blur_reduce_from, DM_PROFILE_MAX_GAUSSIANS - 1);
    else if (desc->blur_reduce_shift < 0 || desc->blur_reduce_shift > 3)
        rc = dm_fail(err, DM_ERR_RANGE, "renderer: blur_reduce_shift %d, expected 0 (1), 1, 2 or 3",
                     desc->blur_reduce_shift);
    else if (desc->blur_reduce_from > 0 && a->scene->effects[DM_EFFECT_SUBSURFACE] && (r->irr_size >> shift) < 8)
        rc = dm_fail(err, DM_ERR_RANGE, "renderer: irradiance size %d >> blur_reduce_shift %d is below 8 texels",
                     r->irr_size, shift);
    if (rc == DM_OK) rc = dm_render_plan_build(&r->scene, DM_VIEW_FINAL, 0, &r->plan, err);
    if (rc == DM_OK) rc = check_assets(a, &r->plan, &r->profile, err);
    for (int i = 0; rc == DM_OK && i < r->plan.pass_count; ++i) {
        dm_pass_kind k = r->plan.passes[i].kind;
        r->ts_pass_count += k == DM_PASS_SHADOW || k == DM_PASS_IRRADIANCE || k == DM_PASS_BLUR_U || k == DM_PASS_BLUR_V;
    }
    if (rc != DM_OK) {
        free(r);
        return rc;
    }
    const char *name = (const char *)glGetString(GL_RENDERER);
    snprintf(r->gl_name, sizeof r->gl_name, "%s", name ? name : "unknown");
    r->timing_cpu = strstr(r->gl_name, "llvmpipe") || strstr(r->gl_name, "softpipe") ||
                    strstr(r->gl_name, "Software") || strstr(r->gl_name, "swrast");
    glGetError(); /* a context may start with a stale error */

    rc = upload_assets(r, a, err);
    if (rc == DM_OK) rc = make_targets(r, err);
    for (int k = 0; k < DM_PASS_KIND_COUNT && rc == DM_OK; ++k) {
        bool needed = k == DM_PASS_FINAL || k == DM_PASS_VIEW ||
                      (k == DM_PASS_SHADOW && r->plan.shadow_count > 0) ||
                      ((k == DM_PASS_IRRADIANCE || k == DM_PASS_BLUR_U) && r->plan.effects[DM_EFFECT_SUBSURFACE]) ||
                      (k == DM_PASS_BACKGROUND && dm_render_plan_find(&r->plan, "background") >= 0) ||
                      ((k == DM_PASS_GLOW_BRIGHT || k == DM_PASS_GLOW_BLUR_U || k == DM_PASS_GLOW_ADD) &&
                       r->plan.effects[DM_EFFECT_GLOW]) ||
                      (k == DM_PASS_TONEMAP && r->plan.effects[DM_EFFECT_TONEMAP]);
        if (needed) rc = build_program(r, pass_shader[k], &r->prog[k], err);
    }
    if (rc == DM_OK) {
        r->prog[DM_PASS_BLUR_V] = r->prog[DM_PASS_BLUR_U];
        r->prog[DM_PASS_GLOW_BLUR_V] = r->prog[DM_PASS_GLOW_BLUR_U];
        if (!r->timing_cpu) glGenQueries(DM_PLAN_MAX_PASSES, r->queries);
        if (r->plan.effects[DM_EFFECT_SUBSURFACE]) prepare_blur(r, 1.0f);
        rc = gl_check("renderer setup", err);
    }
    if (rc != DM_OK) {
        dm_renderer_destroy(r);
        return rc;
    }
    *out = r;
    return DM_OK;
}

void dm_renderer_destroy(dm_renderer *r)
{
    if (!r) return;
    for (int k = 0; k < DM_PASS_KIND_COUNT; ++k)
        if (r->prog[k] && k != DM_PASS_BLUR_V && k != DM_PASS_GLOW_BLUR_V) glDeleteProgram(r->prog[k]);
    GLuint tex[] = {r->tex_albedo,    r->tex_normal,     r->tex_spec,   r->tex_rough,      r->tex_beckmann,
                    r->tex_rho_dt,    r->tex_env_brdf, r->tex_mask,     r->tex_background,
                    r->tex_white,     r->tex_black, r->tex_env_array,      r->tmp_tex,        r->screen_tex, r->tmp_small_tex, r->view_tex,
                    r->glow_tex[0],   r->glow_tex[1],    r->display_tex};
    for (size_t i = 0; i < sizeof tex / sizeof tex[0]; ++i)
        if (tex[i]) glDeleteTextures(1, &tex[i]);
    for (int k = 0; k < DM_PROFILE_MAX_GAUSSIANS; ++k) {
        if (r->tex_stretch[k]) glDeleteTextures(1, &r->tex_stretch[k]);
        if (r->irr_tex[k]) glDeleteTextures(1, &r->irr_tex[k]);
        if (r->irr_fbo[k]) glDeleteFramebuffers(1, &r->irr_fbo[k]);
    }
    for (int k = 0; k < DM_RENDER_ENV_LEVELS_MAX; ++k)
        if (r->tex_env_level[k]) glDeleteTextures(1, &r->tex_env_level[k]);
    for (int k = 0; k < DM_PLAN_MAX_SHADOWS; ++k) {
        if (r->shadow_fbo[k]) glDeleteFramebuffers(1, &r->shadow_fbo[k]);
        if (r->shadow_tex[k]) glDeleteTextures(1, &r->shadow_tex[k]);
    }
    GLuint fbo[] = {r->tmp_fbo,     r->tmp_small_fbo, r->screen_fbo, r->glow_fbo[0],
                    r->glow_fbo[1], r->display_fbo,   r->view_fbo};
    for (size_t i = 0; i < sizeof fbo / sizeof fbo[0]; ++i)
        if (fbo[i]) glDeleteFramebuffers(1, &fbo[i]);
    if (r->screen_depth) glDeleteRenderbuffers(1, &r->screen_depth);
    if (r->vbo) glDeleteBuffers(1, &r->vbo);
    if (r->ebo) glDeleteBuffers(1, &r->ebo);
    if (r->vao_mesh) glDeleteVertexArrays(1, &r->vao_mesh);
    if (r->vao_empty) glDeleteVertexArrays(1, &r->vao_empty);
    if (!r->timing_cpu && r->queries[0]) glDeleteQueries(DM_PLAN_MAX_PASSES, r->queries);
    free(r);
}

/* ---- per-frame state ------------------------------------------------------------------ */

static void frame_lights(dm_renderer *r, float rotation_deg)
{
    const dm_scene *s = &r->scene;
    float a = (float)(rotation_deg * DM_PI / 180.0), c = cosf(a), sn = sinf(a);
    for (int i = 0; i < s->light_count; ++i) {
        const dm_light *l = &s->lights[i];
        const float *v = l->type == DM_LIGHT_DIRECTIONAL ? l->direction : l->position;
        float x = c * v[0] + sn * v[2], z = -sn * v[0] + c * v[2];
        r->light_pos[i][0] = x;
        r->light_pos[i][1] = v[1];
        r->light_pos[i][2] = z;
        r->light_pos[i][3] = l->type == DM_LIGHT_DIRECTIONAL ? 0.0f : 1.0f;
        if (l->type == DM_LIGHT_DIRECTIONAL) v3_norm(r->light_pos[i]);
        for (int k = 0; k < 3; ++k) r->light_color[i][k] = l->color[k] * l->intensity;
        r->light_shadow[i] = -1;
    }
    for (int j = 0; j < r->plan.shadow_count; ++j) {
        int i = r->plan.shadow_light[j];
        r->light_shadow[i] = j;
        float view[16], proj[16], eye[3], up[3] = {0, 1, 0};
        float rad = r->radius;
        if (r->light_pos[i][3] == 0.0f) {
            for (int k = 0; k < 3; ++k) eye[k] = r->center[k] + r->light_pos[i][k] * 2.0f * rad;
            look_at(view, eye, r->center, up, NULL, NULL, NULL);
            ortho(proj, rad * 1.02f, 0.5f * rad, 3.5f * rad);
        } else {
            float d3[3];
            memcpy(eye, r->light_pos[i], sizeof eye);
            v3_sub(d3, r->center, eye);
            float d = sqrtf(v3_dot(d3, d3));
            if (d > rad * 1.01f)
                perspective(proj, 2.0f * asinf(rad / d) * 1.05f, 1.0f, fmaxf(d - rad, 0.01f * rad) * 0.9f,
                            d + rad * 1.1f);
            else
                perspective(proj, (float)(150.0 * DM_PI / 180.0), 1.0f, 0.01f * rad, d + rad * 1.1f);
            look_at(view, eye, r->center, up, NULL, NULL, NULL);
        }
        mat_mul(r->light_matrix[i], proj, view);
    }
}

static void frame_camera(dm_renderer *r)
{
    const dm_scene *s = &r->scene;
    float view[16], proj[16], d3[3];
    memcpy(r->eye, s->camera_eye, sizeof r->eye);
    look_at(view, s->camera_eye, s->camera_target, s->camera_up, r->cam_right, r->cam_up, r->cam_fwd);
    v3_sub(d3, r->center, r->eye);
    float d = sqrtf(v3_dot(d3, d3)), rad = r->radius;
    float n = fmaxf(d - 2.0f * rad, 0.01f * rad), f = d + 2.0f * rad;
    float aspect = (float)r->width / (float)r->height;
    float fov = (float)(s->fov_y_deg * DM_PI / 180.0);
    perspective(proj, fov, aspect, n, f);
    mat_mul(r->view_proj, proj, view);
    float t = tanf(0.5f * fov);
    for (int k = 0; k < 3; ++k) {
        r->cam_right[k] *= t * aspect;
        r->cam_up[k] *= t;
    }
}

static void set_light_uniforms(const dm_renderer *r, GLuint p)
{
    const dm_scene *s = &r->scene;
    glUniform4fv(loc(p, "u_light_pos"), s->light_count, &r->light_pos[0][0]);
    glUniform3fv(loc(p, "u_light_color"), s->light_count, &r->light_color[0][0]);
    glUniform1iv(loc(p, "u_light_shadow"), s->light_count, r->light_shadow);
    glUniformMatrix4fv(loc(p, "u_light_matrix"), s->light_count, GL_FALSE, &r->light_matrix[0][0]);
    u1f(p, "u_shadow_normal_offset", 3.0f * r->radius / (float)r->shadow_size);
    u1f(p, "u_shadow_texel", 1.0f / (float)r->shadow_size);
}

static void set_surface_uniforms(const dm_renderer *r, GLuint p)
{
    const dm_scene *s = &r->scene;
    u1i(p, "u_has_normal_map", r->has_normal_map);
    u1i(p, "u_has_roughness_map", r->has_roughness_map);
    u1f(p, "u_roughness", s->roughness);
    u1f(p, "u_roughness_scale", r->roughness_scale);
    u1f(p, "u_rho_s", s->rho_s);
    glUniform3fv(loc(p, "u_sh"), DM_RENDER_SH_COUNT, &r->env_sh[0][0]);
    u1f(p, "u_env_intensity", s->env_intensity);
    u1f(p, "u_env_rotation", (float)(s->env_rotation_deg * DM_PI / 180.0));
    u1f(p, "u_mix", s->mix);
}

static void bind(int unit, GLenum target, GLuint tex)
{
    glActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    glBindTexture(target, tex);
}

static void bind_surface(const dm_renderer *r)
{
    bind(UNIT_ALBEDO, GL_TEXTURE_2D, r->tex_albedo ? r->tex_albedo : r->tex_white);
    bind(UNIT_NORMAL, GL_TEXTURE_2D, r->tex_normal ? r->tex_normal : r->tex_white);
    bind(UNIT_SPECULAR, GL_TEXTURE_2D, r->tex_spec ? r->tex_spec : r->tex_white);
    bind(UNIT_ROUGHNESS, GL_TEXTURE_2D, r->tex_rough ? r->tex_rough : r->tex_white);
    bind(UNIT_BECKMANN, GL_TEXTURE_2D, r->tex_beckmann ? r->tex_beckmann : r->tex_black);
    bind(UNIT_RHO_DT, GL_TEXTURE_2D, r->tex_rho_dt ? r->tex_rho_dt : r->tex_black);
    bind(UNIT_ENV_BRDF, GL_TEXTURE_2D, r->tex_env_brdf ? r->tex_env_brdf : r->tex_black);
    for (int k = 0; k < DM_RENDER_ENV_LEVELS_MAX; ++k)
        bind(UNIT_ENV_LEVEL0 + k, GL_TEXTURE_2D, r->tex_env_level[k] ? r->tex_env_level[k] : r->tex_black);
    for (int k = 0; k < DM_PLAN_MAX_SHADOWS; ++k)
        if (r->shadow_tex[k]) bind(UNIT_SHADOW + k, GL_TEXTURE_2D, r->shadow_tex[k]);
    if (r->tex_env_array) bind(UNIT_ENV_ARRAY, GL_TEXTURE_2D_ARRAY, r->tex_env_array);
}

static void draw_fullscreen(const dm_renderer *r)
{
    glBindVertexArray(r->vao_empty);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

static void draw_mesh(const dm_renderer *r)
{
    glBindVertexArray(r->vao_mesh);
    glDrawElements(GL_TRIANGLES, r->index_count, GL_UNSIGNED_INT, NULL);
}

static void target_begin(GLuint fbo, int w, int h)
{
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, w, h);
}

/* ---- passes --------------------------------------------------------------------------- */

static void pass_shadow(dm_renderer *r, int j)
{
    int i = r->plan.shadow_light[j];
    GLuint p = r->prog[DM_PASS_SHADOW];
    target_begin(r->shadow_fbo[j], r->shadow_size, r->shadow_size);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.5f, 4.0f);
    glUseProgram(p);
    glUniformMatrix4fv(loc(p, "u_matrix"), 1, GL_FALSE, r->light_matrix[i]);
    draw_mesh(r);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_DEPTH_TEST);
}

static void pass_irradiance(dm_renderer *r)
{
    GLuint p = r->prog[DM_PASS_IRRADIANCE];
    target_begin(r->irr_fbo[0], r->irr_size, r->irr_size);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    glUseProgram(p);
    set_light_uniforms(r, p);
    set_surface_uniforms(r, p);
    bind_surface(r);
    draw_mesh(r);
}

static void pass_blur(dm_renderer *r, int k, bool along_v)
{
    GLuint p = r->prog[DM_PASS_BLUR_U];
    /* the U pass already writes at level k's size (the taps read level k−1 by UV) */
    int n = r->level_size[k];
    bool small = n != r->irr_size;
    GLuint tmp_tex = small ? r->tmp_small_tex : r->tmp_tex, tmp_fbo = small ? r->tmp_small_fbo : r->tmp_fbo;
    target_begin(along_v ? r->irr_fbo[k] : tmp_fbo, n, n);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(p);
    int s = k - 1 < r->stretch_count - 1 ? k - 1 : r->stretch_count - 1;
    bind(UNIT_SRC, GL_TEXTURE_2D, along_v ? tmp_tex : r->irr_tex[k - 1]);
    bind(UNIT_STRETCH, GL_TEXTURE_2D, r->tex_stretch[s]);
    u2f(p, "u_dir", along_v ? 0.0f : 1.0f, along_v ? 1.0f : 0.0f);
    glUniform1fv(loc(p, "u_offset_mm"), r->taps, r->blur_offset[k]);
    glUniform1fv(loc(p, "u_weight"), r->taps, r->blur_weight);
    draw_fullscreen(r);
}

/* The levels and their weights for dm_diffusion (common.glsl), in the final pass and the
 * diffusion view alike; absent levels read black. */
static void bind_levels(const dm_renderer *r, GLuint p)
{
    int levels = r->plan.effects[DM_EFFECT_SUBSURFACE] ? r->profile.count : 0;
    if (levels) glUniform3fv(loc(p, "u_level_weight"), levels, &r->level_weight[0][0]);
    for (int k = 0; k < 8; ++k) bind(UNIT_LEVEL0 + k, GL_TEXTURE_2D, k < levels ? r->irr_tex[k] : r->tex_black);
}

static void pass_final(dm_renderer *r, int mode)
{
    GLuint p = r->prog[DM_PASS_FINAL];
    target_begin(r->screen_fbo, r->width, r->height);
    glClearColor(0, 0, 0, 0); /* alpha: 1 where the head is drawn, 0 elsewhere (coverage) */
    glDepthMask(GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    if (mode == 4) {
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    } else {
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);
    }
    glUseProgram(p);
    glUniformMatrix4fv(loc(p, "u_view_proj"), 1, GL_FALSE, r->view_proj);
    glUniform3fv(loc(p, "u_eye"), 1, r->eye);
    u1i(p, "u_mode", mode);
    set_light_uniforms(r, p);
    set_surface_uniforms(r, p);
    bind_surface(r);
    glUniform1fv(loc(p, "u_env_level_m"), DM_RENDER_ENV_LEVELS_MAX, r->env_level_m);
    bind_levels(r, p);
    draw_mesh(r);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_CULL_FACE);
    glDisable(GL_DEPTH_TEST);
}

static void pass_background(dm_renderer *r)
{
    GLuint p = r->prog[DM_PASS_BACKGROUND];
    target_begin(r->screen_fbo, r->width, r->height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_FALSE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE); /* the background is not skin: alpha stays 0 */
    glUseProgram(p);
    glUniform3fv(loc(p, "u_cam_forward"), 1, r->cam_fwd);
    glUniform3fv(loc(p, "u_cam_right"), 1, r->cam_right);
    glUniform3fv(loc(p, "u_cam_up"), 1, r->cam_up);
    u1f(p, "u_env_rotation", (float)(r->scene.env_rotation_deg * DM_PI / 180.0));
    u1f(p, "u_env_intensity", r->scene.env_intensity);
    bind(UNIT_BACKGROUND, GL_TEXTURE_2D, r->tex_background);
    draw_fullscreen(r);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glDisable(GL_DEPTH_TEST);
}

static void pass_glow(dm_renderer *r, dm_pass_kind kind)
{
    int gw = r->width / 2 > 0 ? r->width / 2 : 1, gh = r->height / 2 > 0 ? r->height / 2 : 1;
    GLuint p = r->prog[kind];
    glUseProgram(p);
    glDisable(GL_DEPTH_TEST);
    if (kind == DM_PASS_GLOW_BRIGHT) {
        target_begin(r->glow_fbo[0], gw, gh);
        bind(UNIT_SRC, GL_TEXTURE_2D, r->screen_tex);
        u1f(p, "u_threshold", r->scene.glow_threshold);
    } else if (kind == DM_PASS_GLOW_BLUR_U) {
        target_begin(r->glow_fbo[1], gw, gh);
        bind(UNIT_SRC, GL_TEXTURE_2D, r->glow_tex[0]);
        u2f(p, "u_step", 1.0f / (float)gw, 0.0f);
    } else if (kind == DM_PASS_GLOW_BLUR_V) {
        target_begin(r->glow_fbo[0], gw, gh);
        bind(UNIT_SRC, GL_TEXTURE_2D, r->glow_tex[1]);
        u2f(p, "u_step", 0.0f, 1.0f / (float)gh);
    } else {
        target_begin(r->screen_fbo, r->width, r->height);
        bind(UNIT_SRC, GL_TEXTURE_2D, r->glow_tex[0]);
        u1f(p, "u_intensity", r->scene.glow_intensity);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
    }
    draw_fullscreen(r);
    glDisable(GL_BLEND);
}

static void pass_tonemap(dm_renderer *r)
{
    GLuint p = r->prog[DM_PASS_TONEMAP];
    target_begin(r->display_fbo, r->width, r->height);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(p);
    bind(UNIT_SRC, GL_TEXTURE_2D, r->screen_tex);
    u1f(p, "u_exposure_scale", exp2f(r->scene.exposure));
    draw_fullscreen(r);
}

/* The texture a texture view shows and its size in texels. */
static GLuint view_source(const dm_renderer *r, int *w, int *h, int *cov_shift)
{
    const dm_render_plan *pl = &r->plan;
    int k = pl->view_index;
    GLuint tex;
    *cov_shift = 0;
    if (pl->view == DM_VIEW_SHADOW) {
        *w = *h = r->shadow_size;
        return r->shadow_tex[k];
    }
    if (pl->view == DM_VIEW_STRETCH) {
        tex = r->tex_stretch[k < r->stretch_count ? k : r->stretch_count - 1];
        glBindTexture(GL_TEXTURE_2D, tex);
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, w);
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, h);
        return tex;
    }
    int level = pl->view == DM_VIEW_BLUR ? k : 0; /* irradiance, diffusion: level 0's size */
    *w = *h = r->level_size[level];
    while ((r->level_size[level] << *cov_shift) < r->irr_size) ++*cov_shift;
    return r->irr_tex[level];
}

/* Texture views: the texels at their own size into "view" (RGBA32F, full precision, alpha =
 * coverage), then that target stretched over the screen for display. */
static void pass_view(dm_renderer *r, const dm_frame_options *opt)
{
    GLuint p = r->prog[DM_PASS_VIEW];
    const dm_render_plan *pl = &r->plan;
    int w = 1, h = 1, shift = 0;
    GLuint src = view_source(r, &w, &h, &shift);
    target *vt = &r->targets[r->view_target];
    if (vt->width != w || vt->height != h) {
        glBindTexture(GL_TEXTURE_2D, r->view_tex);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, h, 0, GL_RGBA, GL_FLOAT, NULL);
        vt->width = w, vt->height = h;
    }
    target_begin(r->view_fbo, w, h);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(p);
    u1f(p, "u_scale", opt->view_scale > 0 ? opt->view_scale : 1.0f);
    u2f(p, "u_size", (float)w, (float)h);
    u1i(p, "u_cov_shift", shift);
    bind_levels(r, p);
    if (pl->view == DM_VIEW_SHADOW) {
        u1i(p, "u_mode", 2);
        bind(UNIT_DEPTH, GL_TEXTURE_2D, src);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_NONE);
        draw_fullscreen(r);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    } else {
        bool stretch = pl->view == DM_VIEW_STRETCH;
        u1i(p, "u_mode", stretch ? 1 : pl->view == DM_VIEW_DIFFUSION ? 3 : 0);
        bind(UNIT_SRC, GL_TEXTURE_2D, src);
        if (stretch) {
            bind(UNIT_MASK, GL_TEXTURE_2D, r->tex_mask ? r->tex_mask : r->tex_black);
            u1i(p, "u_has_mask", r->tex_mask != 0);
        }
        draw_fullscreen(r);
    }
    /* display copy */
    target_begin(r->screen_fbo, r->width, r->height);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    u1i(p, "u_mode", 4);
    bind(UNIT_SRC, GL_TEXTURE_2D, r->view_tex);
    draw_fullscreen(r);
    r->view_in_target = true;
}

static void run_pass(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt)
{
    static const int modes[DM_VIEW_COUNT] = {[DM_VIEW_FINAL] = 0,   [DM_VIEW_SPECULAR] = 1,
                                             [DM_VIEW_DIFFUSE] = 2, [DM_VIEW_UV_TEST] = 3,
                                             [DM_VIEW_WIREFRAME] = 4};
    switch (ps->kind) {
    case DM_PASS_SHADOW: pass_shadow(r, ps->index); break;
    case DM_PASS_IRRADIANCE: pass_irradiance(r); break;
    case DM_PASS_BLUR_U: pass_blur(r, ps->index, false); break;
    case DM_PASS_BLUR_V: pass_blur(r, ps->index, true); break;
    case DM_PASS_FINAL: pass_final(r, modes[r->plan.view]); break;
    case DM_PASS_BACKGROUND: pass_background(r); break;
    case DM_PASS_GLOW_BRIGHT:
    case DM_PASS_GLOW_BLUR_U:
    case DM_PASS_GLOW_BLUR_V:
    case DM_PASS_GLOW_ADD: pass_glow(r, ps->kind); break;
    case DM_PASS_TONEMAP: pass_tonemap(r); break;
    case DM_PASS_VIEW: pass_view(r, opt); break;
    case DM_PASS_KIND_COUNT: break;
    }
}

dm_result dm_render_frame(dm_renderer *r, const dm_frame_options *opt, dm_error *err)
{
    assert(r && opt);
    dm_render_plan plan;
    dm_result rc = dm_render_plan_build(&r->scene, opt->view, opt->view_index, &plan, err);
    if (rc != DM_OK) return rc;
    r->plan = plan;
    float blur_scale = opt->blur_scale > 0 ? opt->blur_scale : 1.0f;
    if (plan.effects[DM_EFFECT_SUBSURFACE] && blur_scale != r->blur_scale) prepare_blur(r, blur_scale);
    r->roughness_scale = opt->roughness_scale > 0 ? opt->roughness_scale : 1.0f;
    frame_lights(r, opt->light_rotation_deg);
    frame_camera(r);
    glGetError();
    const bool timed = r->desc.timings;
    double t_frame = 0;
    if (timed) {
        glFinish();
        t_frame = dm_now_ms();
    }
    r->tonemapped = false;
    r->view_in_target = false;
    /* reuse_texture_space: the shadow maps, irradiance and blur levels depend on the scene
     * (dm_renderer_set_scene invalidates them), the light rotation and the blur and
     * roughness scales; the camera and the view do not enter texture space. */
    bool reuse = r->desc.reuse_texture_space && r->ts_valid && r->ts_rotation == opt->light_rotation_deg &&
                 r->ts_blur_scale == blur_scale && r->ts_roughness_scale == r->roughness_scale;
    int ts_passes = 0;
    for (int i = 0; i < plan.pass_count; ++i) {
        const dm_pass *ps = &plan.passes[i];
        bool ts = ps->kind == DM_PASS_SHADOW || ps->kind == DM_PASS_IRRADIANCE || ps->kind == DM_PASS_BLUR_U ||
                  ps->kind == DM_PASS_BLUR_V;
        ts_passes += ts;
        if (ts && reuse) {
            r->pass_ms[i] = 0.0;
            continue;
        }
        double t0 = 0;
        if (timed && r->timing_cpu) {
            glFinish();
            t0 = dm_now_ms();
        } else if (timed) {
            glBeginQuery(GL_TIME_ELAPSED, r->queries[i]);
        }
        run_pass(r, ps, opt);
        if (timed && r->timing_cpu) {
            glFinish();
            r->pass_ms[i] = dm_now_ms() - t0;
        } else if (timed) {
            glEndQuery(GL_TIME_ELAPSED);
        }
        if (ps->kind == DM_PASS_TONEMAP) r->tonemapped = true;
        rc = gl_check(ps->name, err);
        if (rc != DM_OK) return rc;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!reuse) { /* valid only when this frame made every texture-space result */
        r->ts_valid = ts_passes == r->ts_pass_count;
        r->ts_rotation = opt->light_rotation_deg;
        r->ts_blur_scale = blur_scale;
        r->ts_roughness_scale = r->roughness_scale;
    }
    if (timed) {
        glFinish();
        r->frame_ms = dm_now_ms() - t_frame;
        if (!r->timing_cpu) {
            double sum = 0;
            for (int i = 0; i < plan.pass_count; ++i) {
                dm_pass_kind k = plan.passes[i].kind;
                if (reuse && (k == DM_PASS_SHADOW || k == DM_PASS_IRRADIANCE || k == DM_PASS_BLUR_U ||
                              k == DM_PASS_BLUR_V))
                    continue; /* skipped: no query ran, pass_ms already 0 */
                GLuint ns = 0;
                glGetQueryObjectuiv(r->queries[i], GL_QUERY_RESULT, &ns);
                r->pass_ms[i] = ns * 1e-6;
                sum += r->pass_ms[i];
            }
            r->frame_ms = sum;
        }
    }
    return gl_check("frame end", err);
}

dm_result dm_renderer_set_scene(dm_renderer *r, const dm_scene *s, dm_error *err)
{
    assert(r && s);
    const dm_scene *o = &r->scene;
    const char *what = NULL;
    for (int e = 0; e < DM_EFFECT_COUNT && !what; ++e)
        if (s->effects[e] != o->effects[e]) what = dm_effect_name((dm_effect)e);
    if (!what && s->light_count != o->light_count) what = "light count";
    for (int i = 0; i < s->light_count && !what; ++i)
        if (s->lights[i].type != o->lights[i].type || s->lights[i].casts_shadow != o->lights[i].casts_shadow)
            what = "a light's type or shadow casting";
    if (!what && s->env_background != o->env_background) what = "environment background";
    if (!what && s->blur_taps != o->blur_taps) what = "blur taps";
    if (what)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT,
                       "renderer: the new scene changes %s, which the pass list depends on; recreate the renderer",
                       what);
    r->scene = *s;
    r->ts_valid = false; /* lights, material, environment: texture space is stale */
    r->scene.profile = r->profile;
    return DM_OK;
}

/* ---- queries and readback ------------------------------------------------------------- */

const dm_render_plan *dm_renderer_plan(const dm_renderer *r)
{
    return &r->plan;
}

void dm_renderer_last_timings(const dm_renderer *r, double *pass_ms, double *frame_ms)
{
    if (pass_ms)
        for (int i = 0; i < r->plan.pass_count; ++i) pass_ms[i] = r->desc.timings ? r->pass_ms[i] : 0.0;
    if (frame_ms) *frame_ms = r->desc.timings ? r->frame_ms : 0.0;
}

const char *dm_renderer_gl_name(const dm_renderer *r)
{
    return r->gl_name;
}

bool dm_renderer_timing_on_cpu(const dm_renderer *r)
{
    return r->timing_cpu;
}

void dm_renderer_size(const dm_renderer *r, int *width, int *height, int *irradiance_size)
{
    if (width) *width = r->width;
    if (height) *height = r->height;
    if (irradiance_size) *irradiance_size = r->irr_size;
}

int dm_renderer_target_count(const dm_renderer *r)
{
    return r->target_count;
}

void dm_renderer_target_info(const dm_renderer *r, int index, dm_target_info *info)
{
    assert(index >= 0 && index < r->target_count);
    const target *t = &r->targets[index];
    info->name = t->name;
    info->width = t->width;
    info->height = t->height;
    info->channels = t->channels;
}

int dm_renderer_find_target(const dm_renderer *r, const char *name)
{
    for (int i = 0; i < r->target_count; ++i)
        if (strcmp(r->targets[i].name, name) == 0) return i;
    return -1;
}

dm_result dm_renderer_read_target(dm_renderer *r, int index, float *out, dm_error *err)
{
    assert(index >= 0 && index < r->target_count);
    const target *t = &r->targets[index];
    glBindFramebuffer(GL_FRAMEBUFFER, t->fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (t->channels == 1) {
        glReadPixels(0, 0, t->width, t->height, GL_DEPTH_COMPONENT, GL_FLOAT, out);
    } else {
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glReadPixels(0, 0, t->width, t->height, GL_RGBA, GL_FLOAT, out);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return gl_check(t->name, err);
}

dm_result dm_renderer_read_linear(dm_renderer *r, float *rgba, dm_error *err)
{
    return dm_renderer_read_target(r, dm_renderer_find_target(r, "screen"), rgba, err);
}

void dm_renderer_view_size(const dm_renderer *r, int *width, int *height)
{
    const target *t = &r->targets[r->view_in_target ? r->view_target : dm_renderer_find_target(r, "screen")];
    *width = t->width;
    *height = t->height;
}

dm_result dm_renderer_read_view(dm_renderer *r, float *rgba, dm_error *err)
{
    return dm_renderer_read_target(r, r->view_in_target ? r->view_target : dm_renderer_find_target(r, "screen"), rgba,
                                   err);
}

static uint8_t srgb8(float c)
{
    c = c > 0 ? (c < 1 ? c : 1) : 0; /* NaN becomes 0 */
    float e = c <= 0.0031308f ? 12.92f * c : 1.055f * powf(c, 1.0f / 2.4f) - 0.055f;
    return (uint8_t)lrintf(e * 255.0f);
}

dm_result dm_renderer_read_display(dm_renderer *r, uint8_t *rgba, dm_error *err)
{
    if (r->tonemapped) {
        glBindFramebuffer(GL_FRAMEBUFFER, r->display_fbo);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        glReadPixels(0, 0, r->width, r->height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        return gl_check("display", err);
    }
    size_t n = (size_t)r->width * r->height;
    float *lin = malloc(n * 4 * sizeof *lin);
    if (!lin) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "display: cannot allocate %zu floats", n * 4);
    dm_result rc = dm_renderer_read_linear(r, lin, err);
    for (size_t i = 0; rc == DM_OK && i < n; ++i) {
        for (int c = 0; c < 3; ++c) rgba[i * 4 + c] = srgb8(lin[i * 4 + c]);
        rgba[i * 4 + 3] = 255;
    }
    free(lin);
    return rc;
}
