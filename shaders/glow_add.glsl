// glow_add.glsl - adds intensity x the blurred bright pass to the screen (additive blending).
uniform sampler2D u_src;
uniform float u_intensity;
#ifdef DM_FRAGMENT /* the vertex stage: common.glsl's full-screen triangle */
in vec2 v_uv;
out vec4 o_color;
void main()
{
    o_color = vec4(u_intensity * texture(u_src, v_uv).rgb, 0.0);
}
#endif
