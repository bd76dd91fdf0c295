// diffusion.glsl - the diffusion pass: the levels' weighted sum (dm_level_sum, common.glsl)
// at each texel centre of the irradiance grid, times the texel's chart coverage (the
// irradiance alpha, 0 or 1), alpha = coverage: the texture the final pass and the diffusion
// view read once per pixel (dm_diffusion with DM_DIFFUSION_SUM), coverage-normalised. Only
// with full-resolution levels (reduced ones are summed per pixel). The blur on the CPU makes
// the same sums itself (lib/render/passes/dm_pass_blur_cpu.c).
uniform vec2 u_size; // the irradiance grid's texels
#ifdef DM_FRAGMENT /* the vertex stage: common.glsl's full-screen triangle */
in vec2 v_uv;
out vec4 o_color;
void main()
{
    float c = texelFetch(u_level[0], ivec2(gl_FragCoord.xy), 0).a;
    o_color = vec4(dm_level_sum(gl_FragCoord.xy / u_size) * c, c);
}
#endif
