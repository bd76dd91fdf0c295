// glow_bright.glsl - bright pass into the half-resolution target: what exceeds the threshold.
uniform sampler2D u_src;
uniform float u_threshold;
#ifdef DM_FRAGMENT /* the vertex stage: common.glsl's full-screen triangle */
in vec2 v_uv;
out vec4 o_color;
void main()
{
    // The bilinear tap at a half-resolution texel centre averages the 2x2 block under it.
    vec3 c = texture(u_src, v_uv).rgb;
    o_color = vec4(max(c - vec3(u_threshold), vec3(0.0)), 1.0);
}
#endif
