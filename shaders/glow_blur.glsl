// glow_blur.glsl - a 9-tap Gaussian (sigma 2 texels of the half-resolution target) along u_step,
// in 5 bilinear fetches.
uniform sampler2D u_src;
uniform vec2 u_step; // one texel along x or y, in UV
#ifdef DM_FRAGMENT /* the vertex stage: common.glsl's full-screen triangle */
in vec2 v_uv;
out vec4 o_color;
void main()
{
    // exp(-i^2 / 8), normalised (sigma = 2 texels, +-4 taps: 0.20416, 0.18017, 0.12383, 0.06628,
    // 0.02763), taken as 5 bilinear fetches: each pair (1, 2) and (3, 4) at its weighted mean
    // offset with the pair's summed weight (the taps lie on texel centres across the blur).
    const float w0 = 0.20416, w12 = 0.18017 + 0.12383, w34 = 0.06628 + 0.02763;
    const float o12 = (0.18017 + 2.0 * 0.12383) / w12, o34 = (3.0 * 0.06628 + 4.0 * 0.02763) / w34;
    vec3 s = w0 * texture(u_src, v_uv).rgb;
    s += w12 * (texture(u_src, v_uv + u_step * o12).rgb + texture(u_src, v_uv - u_step * o12).rgb);
    s += w34 * (texture(u_src, v_uv + u_step * o34).rgb + texture(u_src, v_uv - u_step * o34).rgb);
    o_color = vec4(s, 1.0);
}
#endif
