/* dm_frame_bind.h — the one binder of shading inputs: uniforms and textures a pass reads
 * from the frame context (camera, lights, surface and environment, blur levels and their sum,
 * the pre-integrated table, translucency's raw shadow depths), chosen by the pass row's
 * `binds`. Bound in a fixed order: later groups may take units of earlier ones (the
 * pre-integrated table takes two level units; a G-buffer bound after takes the levels' or
 * the blur inputs'). */
#ifndef DM_FRAME_BIND_H
#define DM_FRAME_BIND_H

#include "render/frame/dm_frame.h"

enum {
    DMR_BIND_CAMERA = 1u,       /* u_view_proj, u_eye, u_mode (the view's), u_cam_forward (screen space) */
    DMR_BIND_LIGHTS = 2u,       /* lights and shadow-map matrices */
    DMR_BIND_SURFACE = 4u,      /* material and environment uniforms, their textures, the shadow maps */
    DMR_BIND_ENV_LEVELS = 8u,   /* the prefiltered levels' roughness */
    DMR_BIND_LEVELS = 16u,      /* blur levels, their weights, the diffusion sum */
    DMR_BIND_PREINT = 32u,      /* the pre-integrated table and curvature (technique on) */
    DMR_BIND_TRANSLUCENCY = 64u, /* raw shadow depths and the transmittance (effect on) */
    DMR_BIND_MODE0 = 128u,      /* with CAMERA: u_mode 0 whatever the view */
    DMR_BIND_SHADE = DMR_BIND_CAMERA | DMR_BIND_LIGHTS | DMR_BIND_SURFACE | DMR_BIND_ENV_LEVELS | DMR_BIND_LEVELS |
                     DMR_BIND_PREINT | DMR_BIND_TRANSLUCENCY /* every input: the head's shading passes */
};

/* Binds `what` for program p (in use). */
void dmr_bind_inputs(const dmr_frame *f, GLuint p, unsigned what);
/* Undoes what outlives the draw (translucency's sampler objects). */
void dmr_unbind_inputs(const dmr_frame *f, unsigned what);
/* A G-buffer's four textures on the units of p's u_gbuf0..3 (dmr_gbuffer_unit). */
void dmr_bind_gbuffer(GLuint p, const GLuint tex[4]);
/* The first of those units: the blur levels' units, or, in a program that samples the levels
 * (texture-space final), the blur inputs' (UNIT_SRC..). */
int dmr_gbuffer_unit(GLuint p);

#endif
