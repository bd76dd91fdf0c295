/* dm_pack_build_skin.c — a scene's physical skin becomes its profile when it is packed
 * (dm_pack_build_impl.h): the scene reader (core) stored the parameters; the model is
 * offline (bake/dm_skin_profile.h), so it is evaluated and fitted here. */
#include <stdio.h>
#include <string.h>

#include "bake/dm_profile_fit.h"
#include "bake/dm_skin_spec.h"
#include "packer/dm_pack_build_impl.h"

dm_result dmpb_fit_skin(dm_pack_build *j, dm_error *err)
{
    dm_scene_skin *k = &j->scene.skin;
    if (!k->given) return DM_OK;
    char what[DM_SCENE_PATH_SIZE + 64];
    snprintf(what, sizeof what, "%s: $.effects.subsurface.profile.skin", j->scene_path);
    const char *keys[DM_SKIN_KEY_COUNT];
    for (int i = 0; i < k->key_count; ++i) keys[i] = dm_skin_keys[k->key[i]];
    dm_skin_params p;
    dm_result r = dm_skin_spec_pairs(k->preset[0] ? k->preset : NULL, keys, k->value, k->key_count, what, &p, err);
    if (r != DM_OK) return r;
    /* as dermis-fit-profile --skin does by default: the same calls, the same bytes */
    dm_profile_source src; /* ~2 KB: the dense Gaussians */
    if ((r = dm_profile_source_skin(&p, &src, err)) != DM_OK) return r;
    dm_fit_options fo = {0};
    dm_fit_result fr;
    if ((r = dm_profile_fit(&src, &fo, k->preset[0] ? k->preset : "skin", &fr, err)) != DM_OK) return r;
    if ((r = dm_profile_normalize_white(&fr.profile, NULL, err)) != DM_OK) return r;
    j->scene.profile = fr.profile;
    j->skin = *k;
    dm_skin_spec_format(&p, 17, j->skin_spec, sizeof j->skin_spec);
    /* the scene now holds the fitted profile inline: what the pack's scene entry carries and
     * the renderer reads (it never evaluates the model) */
    k->given = false;
    snprintf(j->scene.profile_source, sizeof j->scene.profile_source, "inline");
    return DM_OK;
}
