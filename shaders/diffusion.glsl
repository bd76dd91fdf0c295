// diffusion.glsl - the diffusion pass: the levels' weighted sum (dm_level_sum, common.glsl)
// at each texel centre of the irradiance grid, times the texel's chart coverage (the
// irradiance alpha, 0 or 1), alpha = coverage: the texture the final pass and the diffusion
// view read once per pixel (dm_diffusion with DM_DIFFUSION_SUM), coverage-normalised. Only
// with full-resolution levels (reduced ones are summed per pixel). The blur on the CPU makes
// the same sums itself (lib/render/passes/dm_pass_blur_cpu.c, core/dm_level_sum.h).
//
// DM_THIN: the thin-part map (bake/dm_thin_map.h, N x 2N: layer j in rows [jN, (j+1)N)) gives a
// texel up to two points across a thin part or a fold, (u', v', d mm, 1); each level k then
// adds, right after its own term, w_k exp(-d^2 / 2 v_k) L_k(u', v') per candidate: the light of
// the sheet across, exact for parallel sheets at distance d.
uniform vec2 u_size; // the irradiance grid's texels
#ifdef DM_THIN
uniform sampler2D u_thin;
uniform float u_level_var[8]; // v_k, mm^2
#endif
#ifdef DM_FRAGMENT /* the vertex stage: common.glsl's full-screen triangle */
in vec2 v_uv;
out vec4 o_color;
void main()
{
    float c = texelFetch(u_level[0], ivec2(gl_FragCoord.xy), 0).a;
#ifdef DM_THIN
    ivec2 t = ivec2(gl_FragCoord.xy);
    vec4 c0 = texelFetch(u_thin, t, 0), c1 = texelFetch(u_thin, t + ivec2(0, int(u_size.y)), 0);
    vec3 sum = vec3(0.0);
    for (int k = 0; k < DM_LEVELS; ++k) {
        sum += u_level_weight[k] * dm_level(k, gl_FragCoord.xy / u_size);
        if (c0.w > 0.5) sum += u_level_weight[k] * (exp(-c0.z * c0.z / (2.0 * u_level_var[k])) * dm_level(k, c0.xy));
        if (c1.w > 0.5) sum += u_level_weight[k] * (exp(-c1.z * c1.z / (2.0 * u_level_var[k])) * dm_level(k, c1.xy));
    }
    o_color = vec4(sum * c, c);
#else
    o_color = vec4(dm_level_sum(gl_FragCoord.xy / u_size) * c, c);
#endif
}
#endif
