// blur.glsl - one separable pass of the incremental diffusion blur (level k from k-1) along
// u_dir. Tap offsets are in mm (the kernel's, scaled so its variance is exactly the step's
// variance) and become UV through the stretch map (UV units per mm along u and v). Values are
// premultiplied by coverage (alpha); outside [0, 1]^2 the border is 0, so it drops out too.
uniform sampler2D u_src;
uniform sampler2D u_stretch;
uniform vec2 u_dir; // (1, 0) for u, (0, 1) for v
uniform float u_offset_mm[63];
uniform float u_weight[63];
#ifdef DM_FRAGMENT /* the vertex stage: common.glsl's full-screen triangle */
in vec2 v_uv;
out vec4 o_color;
void main()
{
    vec2 s = texture(u_stretch, v_uv).rg;
    vec2 step_uv = u_dir * dot(u_dir, s);
    vec4 sum = vec4(0.0);
    for (int i = 0; i < DM_TAPS; ++i)
        sum += u_weight[i] * texture(u_src, v_uv + step_uv * u_offset_mm[i]);
    o_color = sum;
}
#endif
