// glow_blur.glsl - a 9-tap Gaussian (sigma 2 texels of the half-resolution target) along u_step.
uniform sampler2D u_src;
uniform vec2 u_step; // one texel along x or y, in UV
#ifdef DM_VERTEX
out vec2 v_uv;
void main()
{
    gl_Position = dm_fullscreen(v_uv);
}
#else
in vec2 v_uv;
out vec4 o_color;
void main()
{
    // exp(-i^2 / 8), normalised: sigma = 2 texels, +-4 taps
    const float w[5] = float[5](0.20416, 0.18017, 0.12383, 0.06628, 0.02763);
    vec3 s = w[0] * texture(u_src, v_uv).rgb;
    for (int i = 1; i < 5; ++i)
        s += w[i] * (texture(u_src, v_uv + u_step * float(i)).rgb + texture(u_src, v_uv - u_step * float(i)).rgb);
    o_color = vec4(s, 1.0);
}
#endif
