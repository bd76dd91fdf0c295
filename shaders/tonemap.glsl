// tonemap.glsl - exposure (stops), Hable's filmic curve (white point 11.2), sRGB encoding.
uniform sampler2D u_src;
uniform float u_exposure_scale; // 2^exposure
uniform sampler2D u_glow;        // DM_GLOW: the blurred bright pass (half resolution)
uniform float u_glow_intensity;
#ifdef DM_FRAGMENT /* the vertex stage: common.glsl's full-screen triangle */
in vec2 v_uv;
out vec4 o_color;
vec3 hable(vec3 x)
{
    const float A = 0.15, B = 0.50, C = 0.10, D = 0.20, E = 0.02, F = 0.30;
    return ((x * (A * x + C * B) + D * E) / (x * (A * x + B) + D * F)) - E / F;
}
void main()
{
    vec3 lin = texelFetch(u_src, ivec2(gl_FragCoord.xy), 0).rgb;
#ifdef DM_GLOW
    // the glow_add pass's sum, made here: screen + intensity x glow, the same float addition
    // its blending did (passes/dm_pass_glow.c adds it to the screen itself when that is read)
    lin += u_glow_intensity * texture(u_glow, v_uv).rgb;
#endif
    vec3 c = max(lin * u_exposure_scale, vec3(0.0));
    // exposure bias 2 as in Hable's published curve, normalised by the white point
    vec3 t = hable(2.0 * c) / hable(vec3(11.2));
    o_color = vec4(dm_srgb_encode(t), 1.0);
}
#endif
