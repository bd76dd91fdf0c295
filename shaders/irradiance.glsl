// irradiance.glsl - the mesh unwrapped into texture space: per texel, light arriving at the
// surface, pre-scatter albedo applied. Alpha is chart coverage (1 where a triangle covers the
// texel centre, cleared to 0 in gutters): the blurs treat rgb as premultiplied by it, so taps
// in gutters drop out and the kernel renormalises over the chart (seams do not darken).
// Defines: DM_ENERGY (1 - rho_s rho_dt), DM_ENV (SH diffuse), DM_TRANSLUCENCY (light through thin parts),
// DM_SEAM (gutter texels within a blur's reach of a UV seam lit where the surface continues).
// Every texel is lit at its point lifted to the smooth surface (dm_smooth_point, common.glsl).
// DM_GBUFFER (the ts_gbuffer pass, once): the surface per texel (that position, geometric and
// shading normal, rho_s, roughness before the frame's scale, albedo) into four float targets,
// depth 0.5 where a triangle covers the texel. DM_DEFERRED (the irradiance pass, each frame):
// common.glsl's full-screen triangle at the far plane, depth test GREATER, each covered texel
// lit from those targets: the same values, so the same result bit for bit, with no raster, no
// map fetches and every SIMD lane on a texel (llvmpipe shades 4x4 blocks; the atlas's
// triangles are ~50 texels, and along their edges most lanes were masked off).
#if defined(DM_VERTEX) && !defined(DM_DEFERRED)
void main()
{
    dm_mesh_vertex(vec4(a_uv * 2.0 - 1.0, 0.0, 1.0));
}
#elif defined(DM_FRAGMENT)
#ifndef DM_DEFERRED /* G-buffer: position, 1 | geometric normal, roughness before the frame's scale | shading normal, rho_s | albedo */
in vec3 v_pos;
in vec3 v_nrm;
in vec4 v_tan;
in vec2 v_uv;
in float v_pn;
#endif
#ifndef DM_GBUFFER
out vec4 o_color;
#endif
uniform sampler2D u_rho_dt;
#ifdef DM_SEAM
uniform sampler2D u_seam;
#endif
uniform vec3 u_sh[9];
uniform float u_env_intensity;
uniform float u_env_rotation;
uniform float u_mix;
void main()
{
#ifdef DM_DEFERRED
    ivec2 q = ivec2(gl_FragCoord.xy);
#ifdef DM_SEAM
    // A gutter texel the seam map continues (seam_mark.glsl gave it the coverage depth) is lit
    // at the texel where the surface goes on across the UV seam (bake/dm_seam_map.h); should
    // that texel be one this raster left uncovered, coverage 0 drops it out as a gutter. No
    // `discard`: with one llvmpipe shades every texel before its depth test (2x this pass).
    float cover = 1.0;
    if (texelFetch(u_gbuf0, q, 0).w == 0.0) {
        vec2 edge = vec2(textureSize(u_gbuf0, 0));
        q = ivec2(floor(texture(u_seam, (vec2(q) + 0.5) / edge).xy * edge));
        cover = texelFetch(u_gbuf0, q, 0).w;
    }
#endif
    vec4 g1 = texelFetch(u_gbuf1, q, 0), g2 = texelFetch(u_gbuf2, q, 0);
    vec3 P = texelFetch(u_gbuf0, q, 0).xyz, Ng = g1.xyz, N = g2.xyz, albedo = texelFetch(u_gbuf3, q, 0).rgb;
    float m0 = g1.w, rho_s = g2.w;
#else
    dm_surf s = dm_surface(v_nrm, v_tan, v_uv); // common.glsl
    vec3 P = dm_smooth_point(v_pos, v_nrm, v_pn), Ng = s.Ng, N = s.N, albedo = s.albedo;
    float m0 = s.m0, rho_s = s.rho_s;
#endif
#ifdef DM_GBUFFER
    o_g0 = vec4(P, 1.0);
    o_g1 = vec4(Ng, m0);
    o_g2 = vec4(N, rho_s);
    o_g3 = vec4(albedo, 1.0);
#else
    float m = min(m0 * u_roughness_scale, 1.0);
    vec3 e = vec3(0.0);
    // No `continue` for lights behind the texel (N.L = 0 gives k = 0 and e += 0, the same
    // floats): llvmpipe does not unroll a loop that continues, and the loop then costs a quarter
    // of this pass (docs/render-quality.md).
    for (int i = 0; i < DM_LIGHTS; ++i) {
        vec3 L = dm_light_dir(i, P);
        float ndl = max(dot(N, L), 0.0);
        float k = ndl * dm_shadow(i, P, Ng);
#ifdef DM_ENERGY
        k *= max(1.0 - rho_s * texture(u_rho_dt, vec2(ndl, m)).r, 0.0);
#endif
        e += u_light_color[i] * k;
    }
#ifdef DM_TRANSLUCENCY
    e += dm_translucency(P, Ng);
#endif
#ifdef DM_ENV
    e += u_env_intensity * dm_sh_irradiance(u_sh, dm_env_rotate(N, u_env_rotation)) / DM_PI;
#endif
#ifdef DM_SEAM
    o_color = vec4(e * pow(max(albedo, vec3(0.0)), vec3(u_mix)) * cover, cover);
#else
    o_color = vec4(e * pow(max(albedo, vec3(0.0)), vec3(u_mix)), 1.0);
#endif
#endif
}
#endif
