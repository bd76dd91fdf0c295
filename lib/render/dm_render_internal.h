/* dm_render_internal.h — what the renderer's modules share (not installed, not a public API).
 *
 * The renderer is a list of passes (dm_render_passes.c holds the one table: kind, shader,
 * module, run function, whether texture-space reuse may skip it). Each technique or effect
 * owns one file and its passes, targets and uploads:
 *   dm_render.c              create, destroy, set_scene, the frame loop over the plan
 *   dm_render_gl.c           GL helpers: formats, uploads, shader programs, matrices
 *   dm_render_targets.c      frame targets (screen, view) and the camera
 *   dm_render_timing.c       per-pass timing (CPU clock around glFinish, or GL queries)
 *   dm_render_readback.c     read-back of targets, display, views
 *   dm_render_shadow.c       lights, light matrices and shadow maps
 *   dm_render_tsd.c          texture-space diffusion (surface, irradiance, stretch-corrected blurs)
 *   dm_render_blur_cpu.c     the same blurs on the CPU, where OpenGL is software
 *   dm_render_ssss.c         screen-space separable SSS (Jimenez et al. 2015)
 *   dm_render_translucency.c light through thin parts (shadow-map thickness)
 *   dm_render_shade.c        the head on screen: G-buffer and final pass
 *   dm_render_env.c          environment uploads and the background pass
 *   dm_render_glow.c, dm_render_tonemap.c, dm_render_view.c   the post passes and debug views
 * Functions are prefixed dmr_; every one needs the renderer's GL context current.
 */
#ifndef DM_RENDER_INTERNAL_H
#define DM_RENDER_INTERNAL_H

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "core/dm_ssss_kernel.h"
#include "render/dm_render.h"
#include "render/dm_render_memory.h"

/* GL side of each pack format (pack/dm_pack.h owns names and sizes). */
typedef struct fmt_gl {
    GLenum internal, format, type;
} fmt_gl;
extern const fmt_gl dmr_formats[DM_TEX_FORMAT_COUNT];

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
    UNIT_DIFFUSION, /* the diffusion pass's sum (DM_DIFFUSION_SUM) */
    UNIT_COUNT,
    /* passes that never bind the blur/view inputs reuse their units: the screen-space combine
     * pass (u_aux, u_spec) and translucency's raw shadow depths (u_tdepth0..3, sampler object) */
    UNIT_SS_AUX = UNIT_STRETCH,
    UNIT_GLOW = UNIT_STRETCH, /* the tonemap pass's glow */
    UNIT_SS_SPEC = UNIT_MASK,
    UNIT_TDEPTH0 = UNIT_SRC, /* UNIT_SRC, UNIT_STRETCH, UNIT_MASK, UNIT_DEPTH */
    /* the pre-integrated technique has no blur levels: its table and curvature take the last two */
    UNIT_PREINT = UNIT_LEVEL0 + 6,
    UNIT_CURVATURE = UNIT_LEVEL0 + 7
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
    /* Texture sizes here are edges: an N-texel edge is an N × N texture. */
    int width, height, irr_edge, shadow_edge, taps;
    int shadow_taps;                            /* 1, 4 or 9 (DM_SHADOW_TAPS) */
    int level_edge[DM_PROFILE_MAX_GAUSSIANS];   /* texels per side of each irradiance level */
    GLenum level_format;                        /* GL_RGBA32F or GL_RGBA16F */
    bool ts_valid;                              /* texture-space results reusable (reuse_texture_space) */
    int ts_pass_count;                          /* shadow + irradiance + blur passes of the final plan */
    float ts_rotation;                          /* the light rotation they were made with, */
    float ts_blur_scale, ts_roughness_scale;    /* and the per-frame scales */
    int stretch_count, env_level_count;
    float env_level_m[DM_RENDER_ENV_LEVELS_MAX];
    float env_sh[DM_RENDER_SH_COUNT][3];
    bool has_normal_map, has_roughness_map, has_mask;
    bool spec_in_normal; /* the specular map is the normal map texture's alpha (DM_SPEC_IN_NORMAL) */
    float center[3], radius;
    float blur_offset[DM_PROFILE_MAX_GAUSSIANS][DM_BLUR_TAPS_MAX]; /* mm, per level k (index k) */
    float blur_weight[DM_BLUR_TAPS_MAX];
    float blur_scale; /* variance scale the blur offsets were made for (1 at create) */
    float level_weight[DM_PROFILE_MAX_GAUSSIANS][3]; /* profile weights / their sum per channel */

    /* screen-space technique (dm_render_ssss.c) */
    bool screen_space;                          /* scene's technique is screen-space (and subsurface on) */
    int ss_taps;
    float ss_kernel[DM_SSSS_MAX_TAPS][4];       /* rgb weight, a = offset mm */
    GLuint ss_diff_tex, ss_aux_tex, ss_spec_tex, ss_fbo, ss_tmp_tex, ss_tmp_fbo;
    /* pre-integrated technique (dm_render_preint.c) */
    GLuint tex_preint, tex_curvature;
    int preint_height;
    float preint_kmax, preint_blend[3];
    /* translucency (dm_render_translucency.c) */
    GLuint tdepth_sampler;                      /* raw depth reads of the shadow maps */
    float light_depth[DM_SCENE_MAX_LIGHTS][4];  /* near, far (mesh units), 1 = orthographic */

    dm_render_plan plan;
    bool tonemapped; /* the last frame's display came from the tonemap pass */
    bool glow_pending; /* the tonemap added the glow; the screen gets it when read (dmr_glow_settle) */

    GLuint vao_mesh, vbo, ebo, vao_empty;
    int index_count;
    GLuint tex_albedo, tex_normal, tex_spec, tex_rough, tex_beckmann, tex_rho_dt, tex_env_brdf;
    GLuint tex_stretch[DM_PROFILE_MAX_GAUSSIANS], tex_mask, tex_env_level[DM_RENDER_ENV_LEVELS_MAX],
        tex_background;
    GLuint tex_white, tex_black;
    GLuint tex_env_array; /* the env levels as one 2D array when they share size and format */
    GLuint shadow_tex[DM_PLAN_MAX_SHADOWS], shadow_fbo[DM_PLAN_MAX_SHADOWS];
    GLuint irr_tex[DM_PROFILE_MAX_GAUSSIANS], irr_fbo[DM_PROFILE_MAX_GAUSSIANS];
    bool diffusion_sum;      /* the final pass and the diffusion view read the diffusion pass's */
    GLuint diff_tex, diff_fbo; /* sum (DM_DIFFUSION_SUM), not the levels per pixel */
    GLuint ts_gbuf_tex[4], ts_gbuf_fbo, ts_depth; /* the texture-space G-buffer and its coverage depth */
    bool ts_gbuf_valid;                           /* made for the current scene */
    GLuint tmp_tex[DM_PROFILE_MAX_GAUSSIANS], tmp_fbo[DM_PROFILE_MAX_GAUSSIANS]; /* level k's U pass target
                                                   (shared between levels of one size) */
    GLuint screen_tex, screen_depth, screen_fbo;
    GLuint gbuf_tex[4], gbuf_fbo;  /* the head's G-buffer (shaded views), with the screen's depth */
    GLuint view_tex, view_fbo; /* texture views at their own size, RGBA32F (resized on demand) */
    int view_target;           /* its index in targets */
    GLuint view_range_of;      /* the map view_lo, view_hi were measured on (stretch/curvature views) */
    float view_lo, view_hi;    /* their colour scale: 1st and 99th percentile */
    float view_gain;           /* the specular view's exposure gain (1 otherwise) */
    bool view_in_target;       /* the last frame was a texture view: read_view reads "view" */
    GLuint glow_tex[2], glow_fbo[2];
    bool glow_cpu;       /* the glow's Gaussian on the CPU (dm_render_glow.c) */
    float *glow_buf[2];  /* its two half-resolution RGBA images */
    GLuint display_tex, display_fbo;
    GLuint blit_tex, blit_fbo; /* the CPU-built display that dm_renderer_blit_display blits from
                                * when the frame is not tonemapped (made on first use) */
    bool has_frame;            /* a frame has run: the display holds a picture */
    GLuint prog[DM_PASS_KIND_COUNT];
    GLuint prog_glow_blur; /* shared by both glow blur passes */

    target targets[MAX_TARGETS];
    int target_count;

    /* per-frame light state */
    float light_pos[DM_SCENE_MAX_LIGHTS][4], light_color[DM_SCENE_MAX_LIGHTS][3];
    float light_matrix[DM_SCENE_MAX_LIGHTS][16];
    float view_proj[16], eye[3], cam_right[3], cam_up[3], cam_fwd[3];

    /* the blur passes on the CPU (dm_render_blur_cpu.c) */
    bool blur_cpu;
    float *cpu_buf[3];                             /* padded level images (core/dm_level_blur.h) */
    float *cpu_step[DM_PROFILE_MAX_GAUSSIANS][2];  /* level k's stretch per texel: U, V pass */
    float *cpu_level, *cpu_tmp;                    /* texel (0, 0) of level cpu_held, of U's result */
    int cpu_held, cpu_tmp_level;                   /* −1: none */
    float *cpu_sum;    /* the diffusion pass's sum, level by level (full-resolution levels) */
    int cpu_sum_level; /* the last level added to it; −1: none this frame */
    bool cpu_syncing;  /* dmr_blur_cpu_sync is running the chain */
    bool cpu_summing;  /* this frame's chain feeds the sum, and no pass reads the levels in GL:
                        * their uploads wait until something does (dmr_blur_cpu_sync) */
    unsigned levels_stale; /* bit k: level k's texture lags the CPU's chain (upload skipped) */

    bool timing_cpu;
    GLuint queries[DM_PLAN_MAX_PASSES];
    double pass_ms[DM_PLAN_MAX_PASSES], frame_ms;
    char gl_name[256];
    float roughness_scale; /* of the current frame */
};


/* ---- small inline helpers ---- */
static inline GLint loc(GLuint p, const char *name)
{
    return glGetUniformLocation(p, name);
}
static inline void u1i(GLuint p, const char *n, int v)
{
    glUniform1i(loc(p, n), v);
}
static inline void u1f(GLuint p, const char *n, float v)
{
    glUniform1f(loc(p, n), v);
}
static inline void u2f(GLuint p, const char *n, float a, float b)
{
    glUniform2f(loc(p, n), a, b);
}
static inline void dmr_bind(int unit, GLenum target, GLuint tex)
{
    glActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    glBindTexture(target, tex);
}
static inline void dmr_draw_fullscreen(const dm_renderer *r)
{
    glBindVertexArray(r->vao_empty);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}
static inline void dmr_draw_mesh(const dm_renderer *r)
{
    glBindVertexArray(r->vao_mesh);
    glDrawElements(GL_TRIANGLES, r->index_count, GL_UNSIGNED_INT, NULL);
}
static inline void dmr_target_begin(GLuint fbo, int w, int h)
{
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, w, h);
}

/* ---- dm_render_memory.c ---- */
/* The sizes dm_renderer_create resolves from the assets and options (zero: the scene's or the
 * defaults): output, irradiance, shadow map, each level's edge under blur_reduce_from (the
 * automatic resolution is dmr_auto_level_edges, once the stretch is checked). */
typedef struct dmr_sizes {
    int width, height, irr_edge, shadow_edge;
    int level_edge[DM_PROFILE_MAX_GAUSSIANS];
} dmr_sizes;
void dmr_resolve_sizes(const dm_render_assets *a, const dm_render_desc *d, dmr_sizes *s);
/* Whether the texture-space blurs (and the glow's) run on the CPU (dm_render_desc.blur_path):
 * the one predicate create and the estimate share. */
bool dmr_blur_cpu_wanted(const dm_render_desc *d, bool software_gl);
/* What the estimate counts, as create resolved it. */
typedef struct dmr_memory_in {
    const dm_render_assets *a;
    const dm_render_plan *plan;
    const dmr_sizes *sizes;
    bool half_levels, diffusion_sum, software_gl;
    bool cpu_blur, cpu_glow; /* the texture-space blurs, the glow's, on the CPU */
} dmr_memory_in;
void dmr_memory_count(const dmr_memory_in *in, dm_render_memory *out);
/* Whether the diffusion pass sums the levels per texel (not per pixel in the final pass). */
bool dmr_diffusion_summed(const dm_render_plan *p, const dm_render_desc *d);
/* Refuses, naming the limit and the largest size that fits, targets beyond the context's
 * limits (dm_render_gl_limits_get, proxy textures); then the estimate beyond the memory
 * available (desc.memory_available_size, else core/dm_memory.h). */
dm_result dmr_check_limits(const dm_renderer *r, const dm_render_assets *a, dm_error *err);

/* ---- dm_render_gl.c ---- */
const char *dmr_format_name(dm_tex_format f);
dm_result dmr_gl_check(const char *what, dm_error *err);
/* Compiles shaders/<file> with common.glsl, the plan's defines and `extra` (or NULL);
 * sampler units set. */
dm_result dmr_build_program(dm_renderer *r, const char *file, const char *extra, GLuint *out, dm_error *err);
dm_result dmr_upload(const dm_texture *t, const char *what, bool mipmaps, GLenum filter, GLuint *out, dm_error *err);
GLuint dmr_solid_texture(uint8_t v);
void dmr_mat_mul(float *o, const float *a, const float *b);
void dmr_v3_sub(float *o, const float *a, const float *b);
float dmr_v3_dot(const float *a, const float *b);
void dmr_v3_cross(float *o, const float *a, const float *b);
float dmr_v3_norm(float *v);
void dmr_look_at(float *m, const float *eye, const float *target, const float *up_hint, float *right, float *up,
                 float *fwd);
void dmr_perspective(float *m, float fovy_rad, float aspect, float n, float f);
void dmr_ortho(float *m, float half, float n, float f);

/* ---- dm_render_targets.c ---- */
void dmr_add_target(dm_renderer *r, const char *name, GLuint fbo, int w, int h, int channels);
dm_result dmr_color_target(dm_renderer *r, const char *name, int w, int h, GLenum internal, GLenum wrap, GLuint *tex,
                           GLuint *fbo, dm_error *err);
/* A G-buffer (deferred shading: a pass rasterises the surface into it, the next shades each
 * pixel or texel once from it, with every SIMD lane on one): four RGBA32F targets named
 * <prefix>0..3, w x h, in one FBO drawing to all four with the depth renderbuffer `depth`,
 * cleared to 0 once (frames write and read only what the surface covers). */
dm_result dmr_gbuffer_targets(dm_renderer *r, const char *prefix, int w, int h, GLuint depth, GLuint tex[4],
                              GLuint *fbo, dm_error *err);
/* The first of the four units of program p's u_gbuf0..3: the blur levels' units, or, in a
 * program that samples the levels (texture-space final), the blur inputs' (UNIT_SRC..). */
int dmr_gbuffer_unit(GLuint p);
/* Binds them to those units. */
void dmr_bind_gbuffer(GLuint p, const GLuint tex[4]);
extern const GLenum dmr_draw_buffers[4]; /* colour attachments 0..3, for glDrawBuffers */
/* Every target the plan needs, in a fixed order (the target indices of dm_render.h). */
dm_result dmr_make_targets(dm_renderer *r, dm_error *err);
void dmr_frame_camera(dm_renderer *r);
/* Clears the bound screen target for a pass drawing the head into it: `extra` (depth, or 0)
 * and the colour to (0, 0, 0, 0), unless the plan's background pass writes every pixel the
 * head leaves (alpha 0 too, as the clear would): 16 bytes a pixel not written twice. */
void dmr_screen_clear(const dm_renderer *r, GLbitfield extra);
void dmr_set_surface_uniforms(const dm_renderer *r, GLuint p);
void dmr_bind_surface(const dm_renderer *r);
void dmr_mesh_bounds(dm_renderer *r, const float *v, int n);

/* ---- dm_render_timing.c ---- */
void dmr_timing_frame_begin(dm_renderer *r, double *t_frame);
void dmr_timing_pass_begin(dm_renderer *r, int i, double *t0);
void dmr_timing_pass_end(dm_renderer *r, int i, double t0);
/* skipped[i]: pass i did not run (texture-space reuse), its time reads 0 */
void dmr_timing_frame_end(dm_renderer *r, double t_frame, const bool *skipped);

/* ---- dm_render_shadow.c ---- */
dm_result dmr_shadow_targets(dm_renderer *r, dm_error *err);
void dmr_frame_lights(dm_renderer *r, float rotation_deg);
void dmr_set_light_uniforms(const dm_renderer *r, GLuint p);
void dmr_pass_shadow(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);

/* ---- dm_render_tsd.c ---- */
dm_result dmr_tsd_check(const dm_render_assets *a, const dm_profile *prof, dm_error *err);
dm_result dmr_tsd_upload(dm_renderer *r, const dm_render_assets *a, dm_error *err);
dm_result dmr_tsd_targets(dm_renderer *r, dm_error *err);
void dmr_prepare_blur(dm_renderer *r, float scale);
/* The automatic blur resolution (dm_render_desc.blur_auto_resolution, without blur_reduce_from):
 * level k at irr_edge >> j, j the largest (<= 3, >= level k-1's, edge >= 8) keeping its total
 * sigma at least DM_BLUR_AUTO_SIGMA texels at the stretch's median along the coarser axis. No
 * change without the option or a stretch map. */
void dmr_auto_level_edges(const dm_render_assets *a, const dm_render_desc *d, const dm_profile *prof, int irr_edge,
                          int level_edge[DM_PROFILE_MAX_GAUSSIANS]);
/* Value i of a stretch level (RG32F or RG16F texels), as float. */
float dmr_stretch_value(const dm_texture *t, size_t i);
/* level_weight: the profile's weights divided by their sum per channel (TSD levels,
 * translucency's T(d)). */
void dmr_profile_weights(dm_renderer *r);
void dmr_bind_levels(const dm_renderer *r, GLuint p);
void dmr_pass_ts_gbuffer(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);
void dmr_pass_irradiance(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);
void dmr_pass_blur(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);

/* ---- dm_render_blur_cpu.c ---- */
/* Decides where the blur runs (desc.blur_path, the GL renderer, the level format) and, on the
 * CPU, allocates its buffers and samples the stretch per texel. After the plan and targets. */
dm_result dmr_blur_cpu_setup(dm_renderer *r, const dm_render_assets *a, dm_error *err);
void dmr_blur_cpu_free(dm_renderer *r);
void dmr_blur_cpu_pass(dm_renderer *r, const dm_pass *ps);
bool dmr_blur_cpu_diffusion(dm_renderer *r);
void dmr_blur_cpu_sync(dm_renderer *r);
void dmr_pass_diffusion(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);

/* ---- dm_render_ssss.c ---- */
dm_result dmr_ssss_setup(dm_renderer *r, const dm_render_assets *a, dm_error *err);
dm_result dmr_ssss_targets(dm_renderer *r, dm_error *err);
void dmr_pass_ss_shade(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);
void dmr_pass_ss_blur(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);

/* ---- dm_render_preint.c ---- */
dm_result dmr_preint_check(const dm_render_assets *a, dm_error *err);
dm_result dmr_preint_upload(dm_renderer *r, const dm_render_assets *a, dm_error *err);
/* Table, curvature and their uniforms for the final pass; no-op without the technique. */
void dmr_preint_bind(const dm_renderer *r, GLuint p);

/* ---- dm_render_translucency.c ---- */
void dmr_translucency_setup(dm_renderer *r);
/* Uniforms and raw depth bindings for a pass that adds transmitted light; no-op when off. */
void dmr_translucency_bind(const dm_renderer *r, GLuint p);
void dmr_translucency_unbind(const dm_renderer *r);

/* ---- dm_render_shade.c, dm_render_env.c, dm_render_glow.c, dm_render_tonemap.c, dm_render_view.c ---- */
void dmr_pass_gbuffer(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);
void dmr_pass_final(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);
void dmr_pass_final_forward(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);
/* The head drawn with program p (final.glsl) into the bound target: uniforms, bindings, mesh.
 * dmr_shade_begin is all of it but the draw (then dmr_translucency_unbind after the draw). */
void dmr_shade_head(dm_renderer *r, GLuint p, int mode);
void dmr_shade_begin(dm_renderer *r, GLuint p, int mode);
dm_result dmr_env_upload(dm_renderer *r, const dm_render_assets *a, dm_error *err);
void dmr_pass_background(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);
dm_result dmr_glow_targets(dm_renderer *r, dm_error *err);
void dmr_glow_free(dm_renderer *r);
void dmr_pass_glow(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);
/* Adds the glow to the screen if the last frame's tonemap added it to the display only. */
void dmr_glow_settle(dm_renderer *r);
dm_result dmr_tonemap_targets(dm_renderer *r, dm_error *err);
void dmr_pass_tonemap(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);
void dmr_pass_view(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);

/* ---- dm_render_passes.c: the one table ---- */
typedef void (*dmr_pass_fn)(dm_renderer *r, const dm_pass *ps, const dm_frame_options *opt);
typedef struct dmr_pass_info {
    const char *shader;   /* shaders/<file>; passes sharing a file share one program */
    const char *module;   /* the file that owns it */
    dmr_pass_fn run;
    bool texture_space;   /* its result depends on lights and scene only (reuse may skip it) */
    const char *defines;  /* appended to the plan's defines for this kind's program, or NULL */
} dmr_pass_info;
const dmr_pass_info *dmr_pass_get(dm_pass_kind kind);
/* Whether the plan made at create needs this kind's program. */
bool dmr_pass_needed(const dm_renderer *r, dm_pass_kind kind);

#endif
