// blur.glsl - one separable pass of the incremental diffusion blur (level k from k-1) along
// u_dir. Tap offsets are in mm (the kernel's, scaled so its variance is exactly the step's
// variance) and become UV through the stretch map (UV units per mm along u and v). Values are
// premultiplied by coverage (alpha); outside [0, 1]^2 the border is 0, so it drops out too.
// DM_SEAM, on the irradiance's own grid (u_check): where the taps reach across one of this
// texel's cuts (u_cuts), a tap's texel whose point (seam_points.glsl) is farther in 3-D from this
// texel's than u_jump.x x the tap's offset + u_jump.y mm is another place of the surface the
// atlas put beside this one, and is left out (core/dm_level_blur.h, the same floats as the CPU's).
uniform sampler2D u_src;
uniform sampler2D u_stretch;
uniform vec2 u_dir; // (1, 0) for u, (0, 1) for v
uniform float u_offset_mm[63];
uniform float u_weight[63];
#ifdef DM_SEAM
uniform sampler2D u_points;
uniform isampler2D u_cuts; // per texel the nearest cuts along u (x, y) and v (z, w): dm_level_blur_cuts
uniform int u_check;
uniform vec2 u_jump; // DM_LEVEL_BLUR_JUMP_FACTOR, DM_LEVEL_BLUR_JUMP_MM (core/dm_level_blur.h)

// Texel j may be read for the texel whose point is me: outside the image, without a point, or near.
bool dm_near(ivec2 j, vec3 me, float reach)
{
    ivec2 n = textureSize(u_points, 0);
    if (any(lessThan(j, ivec2(0))) || any(greaterThanEqual(j, n))) return true;
    vec4 q = texelFetch(u_points, j, 0);
    if (!(q.w > 0.0)) return true;
    vec3 d = q.xyz - me;
    return dot(d, d) <= reach * reach;
}

vec4 dm_src(ivec2 j)
{
    ivec2 n = textureSize(u_src, 0);
    return any(lessThan(j, ivec2(0))) || any(greaterThanEqual(j, n)) ? vec4(0.0) : texelFetch(u_src, j, 0);
}
#endif
#ifdef DM_FRAGMENT /* the vertex stage: common.glsl's full-screen triangle */
in vec2 v_uv;
out vec4 o_color;
void main()
{
    vec2 s = texture(u_stretch, v_uv).rg;
    vec2 step_uv = u_dir * dot(u_dir, s);
    vec4 sum = vec4(0.0);
#ifdef DM_SEAM
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 me = u_check != 0 ? texelFetch(u_points, px, 0) : vec4(0.0);
    bool along_v = u_dir.y > 0.0;
    float nf = float(along_v ? textureSize(u_src, 0).y : textureSize(u_src, 0).x);
    float t0 = (along_v ? v_uv.y : v_uv.x) * nf - 0.5, dt = dot(u_dir, s) * nf;
    float lo = 0.0, hi = 0.0; // the taps' extent (offset 0 included), as the CPU's off_lo, off_hi
    for (int i = 0; i < DM_TAPS; ++i) {
        lo = min(lo, u_offset_mm[i]);
        hi = max(hi, u_offset_mm[i]);
    }
    lo = t0 + dt * lo, hi = t0 + dt * hi;
    ivec4 c4 = u_check != 0 ? texelFetch(u_cuts, px, 0) : ivec4(-1000, 1 << 20, -1000, 1 << 20);
    vec2 cut = vec2(along_v ? c4.zw : c4.xy); // a texel without a point has no cuts
    if (lo < cut.x || hi >= cut.y - 1.0) { // a tap reads a texel across a cut (core/dm_level_blur.c)
        ivec2 next = ivec2(u_dir);
        for (int i = 0; i < DM_TAPS; ++i) {
            float t = clamp(t0 + dt * u_offset_mm[i], -2.0, nf + 1.0), fl = floor(t), f = t - fl;
            ivec2 ja = along_v ? ivec2(px.x, int(fl)) : ivec2(int(fl), px.y), jb = ja + next;
            float reach = u_jump.x * abs(u_offset_mm[i]) + u_jump.y;
            bool ka = (fl >= cut.x && fl < cut.y) || dm_near(ja, me.xyz, reach);
            bool kb = (fl + 1.0 >= cut.x && fl + 1.0 < cut.y) || dm_near(jb, me.xyz, reach);
            vec4 a = dm_src(ja), b = dm_src(jb);
            if (ka && kb) sum += u_weight[i] * (a + f * (b - a));
            else if (ka) sum += u_weight[i] * (a - f * a);
            else if (kb) sum += u_weight[i] * (f * b);
        }
        o_color = sum;
        return;
    }
#endif
    for (int i = 0; i < DM_TAPS; ++i)
        sum += u_weight[i] * texture(u_src, v_uv + step_uv * u_offset_mm[i]);
    o_color = sum;
}
#endif
