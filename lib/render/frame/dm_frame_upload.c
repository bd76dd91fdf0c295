/* dm_frame_upload.c — pack textures on the GL side (formats, checked uploads) and what every
 * shading pass reads that no technique owns: the mesh and its bounds, white and black, the
 * material maps (the specular map in the normal map's alpha where they match), the LUTs. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_mat4.h"
#include "render/frame/dm_frame.h"

/* GL side of each pack format (pack/dm_pack.h owns names and sizes). */
static const struct {
    GLenum internal, format, type;
} formats[DM_TEX_FORMAT_COUNT] = {
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

void dmr_format_gl(dm_tex_format fmt, GLenum *internal, GLenum *format, GLenum *type)
{
    *internal = formats[fmt].internal, *format = formats[fmt].format, *type = formats[fmt].type;
}

dm_result dmr_upload(dmr_frame *f, const dm_texture *t, const char *what, bool mipmaps, GLenum filter, GLuint *out,
                     dm_error *err)
{
    if (!dm_tex_format_get(t->format))
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: texture format %d is not a dm_tex_format", what,
                       (int)t->format);
    if (t->width < 1 || t->height < 1 || t->width > 16384 || t->height > 16384)
        return dm_fail(err, DM_ERR_RANGE, "%s: size %dx%d, expected 1..16384 per side", what, t->width, t->height);
    *out = dmg_texture_2d(&f->gpu, t->width, t->height, formats[t->format].internal, formats[t->format].format,
                          formats[t->format].type, t->texels, mipmaps, filter);
    return dmg_check(what, err);
}

dm_result dmr_need_texture(const dm_texture *t, const char *what, const char *effect, dm_error *err)
{
    if (!t->texels)
        return dm_fail(err, DM_ERR_MISMATCH, "assets: %s is missing, and the %s effect needs it", what, effect);
    return DM_OK;
}

dm_result dmr_frame_check(const dmr_frame *f, const dm_render_assets *a, dm_error *err)
{
    if (!a->vertices || a->vertex_count < 3 || !a->indices || a->index_count < 3 || a->index_count % 3)
        return dm_fail(err, DM_ERR_EMPTY, "assets: mesh has %d vertices and %d indices, expected >= 3 and a multiple of 3",
                       a->vertex_count, a->index_count);
    for (int i = 0; i < a->index_count; ++i)
        if (a->indices[i] >= (uint32_t)a->vertex_count)
            return dm_fail(err, DM_ERR_RANGE, "assets: index %d is %u, expected < vertex_count %d", i,
                           (unsigned)a->indices[i], a->vertex_count);
    dm_result rc = DM_OK;
    if (f->plan.effects[DM_EFFECT_SPECULAR]) rc = dmr_need_texture(&a->beckmann, "the Beckmann LUT", "specular", err);
    if (rc == DM_OK && f->plan.energy_conservation_active)
        rc = dmr_need_texture(&a->rho_dt, "the rho_dt LUT", "energy_conservation", err);
    return rc;
}

static void mesh_bounds(dmr_frame *f, const float *v, int n)
{
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            float x = v[(size_t)i * DM_VERTEX_FLOATS + c];
            lo[c] = fminf(lo[c], x);
            hi[c] = fmaxf(hi[c], x);
        }
    float rad = 0;
    for (int c = 0; c < 3; ++c) f->center[c] = 0.5f * (lo[c] + hi[c]);
    for (int i = 0; i < n; ++i) {
        float d[3];
        dm_v3_sub(d, &v[(size_t)i * DM_VERTEX_FLOATS], f->center);
        rad = fmaxf(rad, dm_v3_dot(d, d));
    }
    f->radius = sqrtf(rad) > 1e-6f ? sqrtf(rad) : 1.0f;
}

static void upload_mesh(dmr_frame *f, const dm_render_assets *a)
{
    f->vao_mesh = dmg_make(&f->gpu, DMG_VERTEX_ARRAY);
    glBindVertexArray(f->vao_mesh);
    glBindBuffer(GL_ARRAY_BUFFER, dmg_make(&f->gpu, DMG_BUFFER));
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)a->vertex_count * DM_VERTEX_STRIDE, a->vertices, GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, dmg_make(&f->gpu, DMG_BUFFER));
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)a->index_count * 4, a->indices, GL_STATIC_DRAW);
    const int offs[4] = {DM_VERTEX_POSITION, DM_VERTEX_NORMAL, DM_VERTEX_TANGENT, DM_VERTEX_UV};
    const int sizes[4] = {3, 3, 4, 2};
    for (int i = 0; i < 4; ++i) {
        glEnableVertexAttribArray((GLuint)i);
        glVertexAttribPointer((GLuint)i, sizes[i], GL_FLOAT, GL_FALSE, DM_VERTEX_STRIDE,
                              (const void *)(size_t)(offs[i] * 4));
    }
    glBindVertexArray(0);
    f->vao_empty = dmg_make(&f->gpu, DMG_VERTEX_ARRAY);
    f->index_count = a->index_count;
    mesh_bounds(f, a->vertices, a->vertex_count);
}

/* The normal map, and the specular map in its alpha when both are there at one size (the
 * normal map's alpha is unused): one trilinear fetch fewer wherever the surface is read, and
 * the same values (both linear 8-bit; mip levels are made per channel). */
static dm_result upload_normal_specular(dmr_frame *f, const dm_render_assets *a, dm_error *err)
{
    const dm_texture *nm = &a->normal_map, *sp = &a->specular_map;
    f->spec_in_normal = nm->texels && sp->texels && nm->format == DM_TEX_RGBA8 && sp->format == DM_TEX_R8 &&
                        nm->width == sp->width && nm->height == sp->height;
    if (!f->spec_in_normal) {
        dm_result rc = DM_OK;
        if (nm->texels) rc = dmr_upload(f, nm, "normal_map", true, GL_LINEAR, &f->tex_normal, err);
        if (rc == DM_OK && sp->texels) rc = dmr_upload(f, sp, "specular_map", true, GL_LINEAR, &f->tex_spec, err);
        return rc;
    }
    size_t n = (size_t)nm->width * (size_t)nm->height;
    uint8_t *both = malloc(n * 4);
    if (!both) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "normal map with specular: %zu bytes", n * 4);
    memcpy(both, nm->texels, n * 4);
    for (size_t i = 0; i < n; ++i) both[i * 4 + 3] = ((const uint8_t *)sp->texels)[i];
    dm_texture t = *nm;
    t.texels = both;
    dm_result rc = dmr_upload(f, &t, "normal map with specular", true, GL_LINEAR, &f->tex_normal, err);
    free(both);
    return rc;
}

/* An optional texture: uploaded when the assets hold it. */
static dm_result upload_if(dmr_frame *f, const dm_texture *t, const char *what, bool mipmaps, GLuint *out,
                           dm_error *err)
{
    return t->texels ? dmr_upload(f, t, what, mipmaps, GL_LINEAR, out, err) : DM_OK;
}

dm_result dmr_frame_upload(dmr_frame *f, const dm_render_assets *a, dm_error *err)
{
    upload_mesh(f, a);
    f->tex_white = dmg_solid_texture(&f->gpu, 255);
    f->tex_black = dmg_solid_texture(&f->gpu, 0);
    const dm_render_plan *p = &f->plan;
    dm_result rc = upload_if(f, &a->albedo, "albedo", true, &f->tex_albedo, err);
    if (rc == DM_OK) rc = upload_normal_specular(f, a, err);
    if (rc == DM_OK) rc = upload_if(f, &a->roughness_map, "roughness_map", true, &f->tex_rough, err);
    if (rc == DM_OK && p->effects[DM_EFFECT_SPECULAR])
        rc = upload_if(f, &a->beckmann, "beckmann", false, &f->tex_beckmann, err);
    if (rc == DM_OK && p->energy_conservation_active)
        rc = upload_if(f, &a->rho_dt, "rho_dt", false, &f->tex_rho_dt, err);
    f->has_normal_map = a->normal_map.texels != NULL;
    f->has_roughness_map = a->roughness_map.texels != NULL;
    if (a->has_env_sh) memcpy(f->env_sh, a->env_sh, sizeof f->env_sh);
    return rc;
}
