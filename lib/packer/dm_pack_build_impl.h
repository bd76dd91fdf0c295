/* dm_pack_build_impl.h — what the pack-building files share (not installed): the helpers
 * of dm_pack_build_job.c and the steps of dm_pack_build_steps.c and dm_pack_build_bake.c. */
#ifndef DM_PACK_BUILD_IMPL_H
#define DM_PACK_BUILD_IMPL_H

#include "packer/dm_pack_build.h"
#include "core/dm_prov.h"

/* The entry into the writer, with its report row. */
dm_result dmpb_add(dm_pack_build *j, const dm_pack_entry *d, const void *data, size_t size, const dm_provenance *prov,
                   const char *source, dm_error *err);
/* An RGBA32F texture baked from the scene's mesh ("baked from MESH" in the report), its four
 * channels named. */
dm_result dmpb_add_mesh_rgba32f(dm_pack_build *j, const char *entry, int width, int height,
                                const char *const channels[4], const float *texels, const dm_provenance *prov,
                                dm_error *err);
const char *dmpb_base_name(const char *path);
/* The scene's mesh, loaded once (the mesh, stretch and curvature steps and the albedo from the
 * skin share it; dm_pack_build_job.c). */
dm_result dmpb_ensure_mesh(dm_pack_build *j, dm_error *err);
void dmpb_mesh_prov(const dm_pack_build *j, dm_provenance *p, const char *what);

/* A scene's physical skin ("profile": {"skin": {…}}): its parameters checked, the profile
 * fitted to it as dermis-fit-profile --skin does by default (six Gaussians, normalised to
 * white), put in the scene as an inline profile (dm_pack_build_skin.c). Nothing to do when
 * the scene names no skin. */
dm_result dmpb_fit_skin(dm_pack_build *j, dm_error *err);
/* material.albedo_from "skin": the albedo map's texels (w × h RGBA8, sRGB, rows bottom-up)
 * become the skin's total reflectance times their luminance detail (bake/dm_albedo_skin.h),
 * in place, weighted by the scene mesh's skin area; the parameters and what came out go into
 * the entry's provenance p and its report line src (dm_pack_build_skin.c). */
dm_result dmpb_albedo_from_skin(dm_pack_build *j, uint8_t *rgba, int w, int h, dm_provenance *p, char *src,
                                size_t src_size, dm_error *err);

/* The steps (dm_pack_build.c runs them from its table). */
dm_result dmpb_step_scene(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_mesh(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_albedo(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_normal(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_specular(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_roughness(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_beckmann(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_directional(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_profile(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_stretch(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_seam(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_thin(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_gather(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_ss_kernel(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_preintegrated(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_curvature(dm_pack_build *j, dm_error *err);
dm_result dmpb_step_environment(dm_pack_build *j, dm_error *err);

#endif
