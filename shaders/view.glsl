// view.glsl - debug view of a texture-space intermediate. Modes 0..3 draw into the "view"
// target at the source's own size, one fragment per texel (texelFetch at gl_FragCoord, so
// the values are the texels themselves, at full float precision); mode 4 then copies that
// target stretched over the screen for display.
// u_mode: 0 level (rgb / alpha, alpha = chart coverage), 1 stretch (u red, v green, mask
// blue; alpha = mask, 1 without one), 2 shadow depth (alpha 1), 3 diffusion (dm_diffusion,
// alpha = chart coverage), 4 copy u_src to the screen. Values x u_scale, no tonemap.
uniform int u_mode;
uniform float u_scale;
uniform vec2 u_size;     // texels of the view target (modes 0..3)
uniform int u_cov_shift; // level texel i covers irradiance texels i << shift (reduced levels)
uniform sampler2D u_src;
uniform sampler2D u_mask;
uniform bool u_has_mask;
uniform sampler2D u_depth;
#ifdef DM_VERTEX
out vec2 v_uv;
void main()
{
    gl_Position = dm_fullscreen(v_uv);
}
#else
in vec2 v_uv;
out vec4 o_color;
// Chart coverage at this texel: the irradiance alpha (0 or 1, rasterised) of the fine texel
// under this texel's centre.
float coverage(ivec2 ij)
{
    return texelFetch(u_level[0], (ij << u_cov_shift) + ((1 << u_cov_shift) >> 1), 0).a;
}
void main()
{
    if (u_mode == 4) {
        o_color = texture(u_src, v_uv);
        return;
    }
    ivec2 ij = ivec2(gl_FragCoord.xy);
    vec3 c;
    float a = 1.0;
    if (u_mode == 0) {
        vec4 t = texelFetch(u_src, ij, 0);
        c = t.a > 1e-4 ? t.rgb / t.a : vec3(0.0);
        a = coverage(ij);
    } else if (u_mode == 3) {
        c = dm_diffusion(gl_FragCoord.xy / u_size);
        a = coverage(ij);
    } else if (u_mode == 1) {
        float m = u_has_mask ? texture(u_mask, gl_FragCoord.xy / u_size).r : 1.0;
        c = vec3(texelFetch(u_src, ij, 0).rg, u_has_mask ? m : 0.0);
        a = m >= 0.5 ? 1.0 : 0.0;
    } else {
        c = vec3(texelFetch(u_depth, ij, 0).r);
    }
    o_color = vec4(c * u_scale, a);
}
#endif
