// diffusion.glsl - the diffusion pass: the levels' weighted sum (dm_level_sum, common.glsl)
// at each texel centre of the irradiance grid, times the texel's chart coverage (the
// irradiance alpha, 0 or 1), alpha = coverage: the texture the final pass and the diffusion
// view read once per pixel (dm_diffusion with DM_DIFFUSION_SUM), coverage-normalised. Only
// with full-resolution levels (reduced ones are summed per pixel). The blur on the CPU makes
// the same sums itself (lib/render/passes/dm_pass_blur_cpu.c, core/dm_level_sum.h).
//
// DM_THIN: the thin-part map (bake/dm_thin_map.h, N x 2N: layer j in rows [jN, (j+1)N)) gives a
// texel up to two points across a thin part or a fold, (u', v', d mm, 1); each level k then
// adds, right after its own term, w_k exp(-d^2 / 2 v_k) L_k(u', v') per candidate within
// d^2 <= DM_THIN_CUT v_k (core/dm_level_sum.h): the light of the sheet across, exact for
// parallel sheets at distance d.
//
// DM_GATHER: the thin gather (bake/dm_thin_gather.h; core/dm_level_sum.h holds the CPU's same
// sums): a texel whose index counts taps for gathered level g takes, for level u_gather_first + g,
// sum_t weight_t * I(uv_s(t)) instead of its own term and the candidates', I level 0 read at the
// site's UV as dm_level reads it (bilinear, coverage-normalised). The index holds the first tap's
// row and column (x, w) and levels 0 and 1's tap counts (y, z); the taps texture the header, the
// sites' UVs, then the runs: with 3 or 4 levels a count tap (levels 2 and 3's), then the taps
// level by level (the site's tap index, weight).
uniform vec2 u_size; // the irradiance grid's texels
#ifdef DM_THIN
uniform sampler2D u_thin;
uniform float u_level_var[8]; // v_k, mm^2
#endif
#ifdef DM_GATHER
uniform sampler2D u_gather_index, u_gather_taps;
uniform int u_gather_first, u_gather_count;
#ifdef DM_FRAGMENT
vec2 dm_gather_tap(int t)
{
    return texelFetch(u_gather_taps, ivec2(t % 4096, t / 4096), 0).xy;
}
vec3 dm_gather_site(float s)
{
    return dm_level(0, dm_gather_tap(int(s)));
}
// gathered level g of the run whose level 0 starts at tap t, n its levels' taps
vec3 dm_gathered(int g, int t, float n[4])
{
    for (int m = 0; m < g; ++m) t += int(n[m]);
    int end = t + int(n[g]);
    vec3 s0 = vec3(0.0), s1 = vec3(0.0); // two sums, as the CPU's
    for (; t + 1 < end; t += 2) {
        vec2 a = dm_gather_tap(t), b = dm_gather_tap(t + 1);
        s0 = s0 + a.y * dm_gather_site(a.x);
        s1 = s1 + b.y * dm_gather_site(b.x);
    }
    if (t < end) {
        vec2 a = dm_gather_tap(t);
        s0 = s0 + a.y * dm_gather_site(a.x);
    }
    return s0 + s1;
}
#endif
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
#ifdef DM_GATHER
    vec4 gix = texelFetch(u_gather_index, t, 0);
    int run = int(gix.x) * 4096 + int(gix.w);
    vec2 more = vec2(0.0); // with 3 or 4 levels the run's count tap: levels 2 and 3's taps
    if (u_gather_count > 2 && gix.y + gix.z > 0.0) more = dm_gather_tap(run), run += 1;
    float gn[4] = float[4](gix.y, gix.z, more.x, more.y);
#endif
    for (int k = 0; k < DM_LEVELS; ++k) {
#ifdef DM_GATHER
        int g = k - u_gather_first;
        if (g >= 0 && g < u_gather_count && gn[g] > 0.0) {
            sum += u_level_weight[k] * dm_gathered(g, run, gn);
            continue;
        }
#endif
        sum += u_level_weight[k] * dm_level(k, gl_FragCoord.xy / u_size);
        float cut = DM_THIN_CUT * u_level_var[k]; /* core/dm_level_sum.h: beyond, exp(-d^2/2v) < e^-18 */
        if (c0.w > 0.5 && c0.z * c0.z <= cut) sum += u_level_weight[k] * (exp(-c0.z * c0.z / (2.0 * u_level_var[k])) * dm_level(k, c0.xy));
        if (c1.w > 0.5 && c1.z * c1.z <= cut) sum += u_level_weight[k] * (exp(-c1.z * c1.z / (2.0 * u_level_var[k])) * dm_level(k, c1.xy));
    }
    o_color = vec4(sum * c, c);
#else
    o_color = vec4(dm_level_sum(gl_FragCoord.xy / u_size) * c, c);
#endif
}
#endif
