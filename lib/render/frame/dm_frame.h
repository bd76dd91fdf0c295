/* dm_frame.h — what every pass shares: the frame context (sizes, the scene and plan, the mesh,
 * the lights and camera of this frame, the shading inputs, the shared targets, and what
 * passes publish for the passes after them), the fixed sampler units, and the draws.
 * Passes read and write each other's results only here; the renderer (dm_render.c) owns
 * one and hands it to every hook. Functions are prefixed dmr_; each needs the renderer's GL
 * context current. */
#ifndef DM_FRAME_H
#define DM_FRAME_H

#include "render/dm_render.h"
#include "render/gpu/dm_gpu.h"
#include "render/input/dm_render_kernel.h"

/* Texture units, fixed per sampler name in every program (dmr_frame_program). */
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
    UNIT_CURVATURE = UNIT_LEVEL0 + 7,
    /* the irradiance pass's seam map: its G-buffer takes UNIT_LEVEL0..+3 */
    UNIT_SEAM = UNIT_LEVEL0 + 4,
    /* the diffusion pass's thin-part map and thin gather: that pass reads the levels and nothing else */
    UNIT_THIN = UNIT_SRC,
    UNIT_GATHER_INDEX = UNIT_STRETCH,
    UNIT_GATHER_TAPS = UNIT_MASK,
    /* the texture views' chart coverage (the texture-space G-buffer's positions, w) */
    UNIT_COVER = UNIT_BACKGROUND,
    /* the blurs' seam points (seam_points.glsl): a blur reads its source, the stretch and these */
    UNIT_POINTS = UNIT_MASK,
    UNIT_CUTS = UNIT_DEPTH
};

/* The pre-integrated technique's inputs to the shading passes (its table and curvature map). */
typedef struct dmr_preint_inputs {
    GLuint table, curvature;
    int height;
    float kmax, blend[3];
} dmr_preint_inputs;

typedef struct dmr_frame dmr_frame;

/* Levels whose textures lag a chain made elsewhere (the blur on the CPU defers uploads
 * nothing reads): bit k stale; sync brings them up to date (set by whoever defers). */
typedef struct dmr_levels_sync {
    unsigned stale;
    void (*sync)(dmr_frame *f, void *state);
    void *state;
} dmr_levels_sync;

struct dmr_frame {
    dmg gpu; /* every GL object and named target */
    dm_scene scene;
    dm_profile profile;
    dm_render_desc desc;
    char shader_dir[4096];
    dm_render_plan plan; /* this frame's (create's until the first frame) */

    /* Texture sizes here are edges: an N-texel edge is an N × N texture. */
    int width, height, irr_edge, shadow_edge, taps;
    int shadow_taps;                          /* 1, 4 or 9 (DM_SHADOW_TAPS) */
    int level_edge[DM_PROFILE_MAX_GAUSSIANS]; /* texels per side of each irradiance level */
    GLenum level_format;                      /* GL_RGBA32F or GL_RGBA16F */
    bool software_gl;                         /* OpenGL runs on the CPU (llvmpipe, softpipe) */
    bool diffusion_sum; /* the final pass and the diffusion view read the diffusion pass's sum
                         * (DM_DIFFUSION_SUM), not the levels per pixel */
    bool blur_cpu;      /* the texture-space blurs run on the CPU (the CPU blur's setup) */
    bool thin_map;      /* the pack's thin-part map is used (dmr_tsd_thin_usable): every plan
                         * drops translucency (dm_render_plan_thin_map) */

    /* the mesh */
    GLuint vao_mesh, vao_empty;
    int index_count;
    float center[3], radius;

    /* shading inputs: material, LUTs, environment (frame uploads; env: the env module) */
    GLuint tex_albedo, tex_normal, tex_spec, tex_rough, tex_beckmann, tex_rho_dt, tex_env_brdf;
    GLuint tex_env_level[DM_RENDER_ENV_LEVELS_MAX];
    GLuint tex_env_array; /* the env levels as one 2D array when they share size and format */
    GLuint tex_white, tex_black;
    int env_level_count;
    float env_level_m[DM_RENDER_ENV_LEVELS_MAX];
    float env_sh[DM_RENDER_SH_COUNT][3];
    bool has_normal_map, has_roughness_map;
    bool spec_in_normal; /* the specular map is the normal map texture's alpha (DM_SPEC_IN_NORMAL) */
    GLuint tex_stretch[DM_PROFILE_MAX_GAUSSIANS], tex_mask; /* texture space's stretch chain */
    GLuint tex_seam; /* the seam map (0 without one): irradiance.glsl's DM_SEAM */
    /* with it, each texel's 3-D point in mm as the irradiance pass lights it (seam_points.glsl,
     * made with the G-buffer, then read back) and where the atlas jumps between them
     * (dm_level_blur_cuts, uploaded as tex_seam_cuts): the blurs leave out taps that jump to
     * another place of the surface (core/dm_level_blur.h). */
    GLuint tex_seam_points, seam_points_fbo, tex_seam_cuts;
    float *seam_points; /* the CPU's copies (NULL when none, or out of memory: no check) */
    int16_t *seam_cuts;
    GLuint tex_thin; /* the thin-part map (0 without one): diffusion.glsl's DM_THIN; the blur on
                      * the CPU keeps its candidates in its own compact copy */
    /* the thin gather in GL (diffusion.glsl's DM_GATHER; 0 without, or when the blur runs on
     * the CPU, which keeps its own compact copy): index, taps, and the header's numbers */
    GLuint tex_gather_index, tex_gather_taps;
    bool gather_ok; /* the pack has a gather at this size that the sums read (dm_pass_tsd.c's upload) */
    int gather_first, gather_count;
    GLuint tex_gather_view; /* the index for the "gather" debug view, and its most taps a texel */
    float gather_view_max;
    GLuint ts_cover_tex; /* texture space's G-buffer positions: w = 1 on the texels a triangle covers */
    int stretch_count;
    dmr_preint_inputs preint;
    GLuint tdepth_sampler; /* raw depth reads of the shadow maps (translucency) */

    /* numbers the passes share */
    dmr_blur_kernel kernel;                          /* the levels' blur at this frame's scale */
    float level_weight[DM_PROFILE_MAX_GAUSSIANS][3]; /* profile weights / their sum per channel
                                                      * × level_scale */
    double level_scale[3]; /* dm_renderer_set_profile_weights' scale_rgb; 1 at create */
    int ss_taps, ss_rows;                            /* the screen-space kernel's taps and rows (defines) */

    /* this frame: lights (turned by the light rotation) and camera */
    float light_pos[DM_SCENE_MAX_LIGHTS][4], light_color[DM_SCENE_MAX_LIGHTS][3];
    float light_matrix[DM_SCENE_MAX_LIGHTS][16];
    float light_depth[DM_SCENE_MAX_LIGHTS][4]; /* near, far (mesh units), 1 = orthographic */
    float view_proj[16], eye[3], cam_right[3], cam_up[3], cam_fwd[3];
    float roughness_scale;

    /* shared targets (dm_frame_targets.c) */
    GLuint screen_tex, screen_depth, screen_fbo;
    GLuint gbuf_tex[4], gbuf_fbo; /* the head's G-buffer (shaded views), with the screen's depth */
    GLuint view_tex, view_fbo;    /* texture views at their own size, RGBA32F (resized on demand) */
    int view_target;              /* its index among the targets */

    /* published by passes for the passes after them */
    GLuint shadow_tex[DM_PLAN_MAX_SHADOWS];
    GLuint level_tex[DM_PROFILE_MAX_GAUSSIANS], level_fbo[DM_PROFILE_MAX_GAUSSIANS]; /* irradiance, blurK */
    GLuint diff_tex, diff_fbo; /* the diffusion pass's sum */
    GLuint glow_tex;           /* the glow at half resolution, for the tonemap */
    dmr_levels_sync levels;
    float view_gain;     /* the specular view's exposure gain (1 otherwise) */
    bool view_in_target; /* the last frame was a texture view: read_view reads "view" */

    GLuint prog[DM_PASS_KIND_COUNT]; /* kinds sharing a shader file and defines share one */
};

static inline void dmr_draw_fullscreen(const dmr_frame *f)
{
    glBindVertexArray(f->vao_empty);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}
static inline void dmr_draw_mesh(const dmr_frame *f)
{
    glBindVertexArray(f->vao_mesh);
    glDrawElements(GL_TRIANGLES, f->index_count, GL_UNSIGNED_INT, NULL);
}

/* Brings the levels in `mask` up to date where a chain deferred their uploads. */
void dmr_levels_need(dmr_frame *f, unsigned mask);
/* u_mode of the shading passes for the plan's view: 0 final, 1 specular, 2 diffuse, 3 uv, 4 wireframe. */
int dmr_view_mode(const dmr_frame *f);

/* ---- dm_frame_scene.c: what a frame's settings make ---- */
/* Light positions and colours turned by rotation_deg, each shadow map's matrix and depth range. */
void dmr_frame_lights(dmr_frame *f, float rotation_deg);
/* The camera's matrix and basis (right and up scaled to the image plane at distance 1). */
void dmr_frame_camera(dmr_frame *f);
/* Whether the blur from level k−1 to k checks its taps for jumps (core/dm_level_blur.h; blur.glsl's
 * u_check): with the seam points read back, on the irradiance's own grid. */
static inline bool dmr_frame_blur_checks(const dmr_frame *f, int k)
{
    return f->seam_points && f->level_edge[k] == f->irr_edge && f->level_edge[k - 1] == f->irr_edge;
}

/* The levels' blur kernel at variance scale `scale`, and their weights. */
void dmr_frame_blur(dmr_frame *f, float scale);

/* ---- dm_frame_upload.c: the mesh and the material ---- */
/* DM_ERR_MISMATCH naming what is missing and the effect that needs it, or DM_OK. */
dm_result dmr_need_texture(const dm_texture *t, const char *what, const char *effect, dm_error *err);
/* What every plan reads: the mesh (indices in range), the specular and energy LUTs it calls for. */
dm_result dmr_frame_check(const dmr_frame *f, const dm_render_assets *a, dm_error *err);
const char *dmr_format_name(dm_tex_format f);
/* A pack texture uploaded (format and size checked), recorded in f's registry. */
dm_result dmr_upload(dmr_frame *f, const dm_texture *t, const char *what, bool mipmaps, GLenum filter, GLuint *out,
                     dm_error *err);
/* GL's (internal, format, type) of a pack format. */
void dmr_format_gl(dm_tex_format fmt, GLenum *internal, GLenum *format, GLenum *type);
/* The mesh (vertex array, bounds), white and black, albedo, normal/specular, roughness, LUTs. */
dm_result dmr_frame_upload(dmr_frame *f, const dm_render_assets *a, dm_error *err);

/* ---- dm_frame_targets.c ---- */
/* The screen (float32 with depth), the view target, the head's G-buffer when deferred. */
dm_result dmr_frame_targets(dmr_frame *f, dm_error *err);

/* ---- dm_frame_program.c ---- */
/* Compiles shaders/<file> with common.glsl, the frame's defines and `extra` (or NULL);
 * sampler units set. */
dm_result dmr_frame_program(dmr_frame *f, const char *file, const char *extra, GLuint *out, dm_error *err);

#endif
