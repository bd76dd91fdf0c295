// glow_blur.glsl - the glow's 9-tap Gaussian (sigma 2 texels of the half-resolution target)
// along u_step, in 5 bilinear fetches: the kernel (core/dm_glow_blur.h, which also runs it on
// the CPU where OpenGL is software) gives the centre's and the pairs' weights and the pairs'
// offsets in texels (each pair (1, 2), (3, 4) at its weighted mean offset, its summed weight).
uniform sampler2D u_src;
uniform vec2 u_step;   // one texel along x or y, in UV
uniform vec3 u_weight; // centre, pair (1, 2), pair (3, 4)
uniform vec2 u_offset; // the pairs' offsets, texels
#ifdef DM_FRAGMENT /* the vertex stage: common.glsl's full-screen triangle */
in vec2 v_uv;
out vec4 o_color;
void main()
{
    vec3 s = u_weight.x * texture(u_src, v_uv).rgb;
    s += u_weight.y * (texture(u_src, v_uv + u_step * u_offset.x).rgb + texture(u_src, v_uv - u_step * u_offset.x).rgb);
    s += u_weight.z * (texture(u_src, v_uv + u_step * u_offset.y).rgb + texture(u_src, v_uv - u_step * u_offset.y).rgb);
    o_color = vec4(s, 1.0);
}
#endif
