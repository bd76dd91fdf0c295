// view.glsl - debug view of a texture-space intermediate. Modes 0..3 draw into the "view"
// target at the source's own size, one fragment per texel (texelFetch at gl_FragCoord, so
// the values are the texels themselves, at full float precision); mode 4 then copies that
// target stretched over the screen for display.
// u_mode: 0 level (rgb / alpha, alpha = chart coverage), 1 stretch (u red, v green, mask
// blue; alpha = mask, 1 without one), 2 shadow depth (alpha 1), 3 diffusion (dm_diffusion,
// alpha = chart coverage), 5 a scalar map's red channel (curvature; alpha 1), 4 copy u_src
// to the screen, 6 show the source map's scalar (the stretch as mm per texel,
// 1 / (width sqrt(s_u s_v)); a scalar map's red) through the turbo colour scale from u_lo
// (blue) to u_hi (red), near black outside the charts; with u_flagged the source is mode 7's
// (value, flag, 0, coverage): the flagged texels through the scale, the other covered ones grey.
// 7 a seam or thin-part map at the irradiance grid into (mm, flag, 0, chart coverage): the
// seam map's (u', v', continued, mm), the thin map's layer 0 (u', v', mm, candidate; its
// nearer point). Values x u_scale, no tonemap.
uniform int u_mode;
uniform float u_scale;
uniform vec2 u_size;     // texels of the view target (modes 0..3)
uniform int u_cov_shift; // level texel i covers irradiance texels i << shift (reduced levels)
uniform sampler2D u_src;
uniform sampler2D u_mask;
uniform bool u_has_mask;
uniform sampler2D u_depth;
uniform sampler2D u_cover; // modes 0, 3: the texture-space G-buffer's positions (w: coverage)
uniform float u_lo, u_hi; // mode 6: the colour scale's ends
uniform bool u_stretch;   // mode 6: u_src holds the stretch (u, v), not a scalar
uniform bool u_flagged;   // mode 6: u_src is mode 7's (value, flag, 0, coverage)
uniform int u_map_kind;   // mode 7: 0 the seam map, 1 the thin-part map, 2 the thin gather's index
// Turbo colour map (Mikhailov 2019, polynomial fit), t in [0, 1]; the same polynomial as the
// legend's on the CPU (dm_render_turbo).
vec3 turbo(float t)
{
    t = clamp(t, 0.0, 1.0);
    vec3 c = vec3(0.13572138, 0.09140261, 0.10667330) +
             t * (vec3(4.61539260, 2.19418839, 12.64194608) +
                  t * (vec3(-42.66032258, 4.84296658, -60.58204836) +
                       t * (vec3(132.13108234, -14.18503333, 110.36276771) +
                            t * (vec3(-152.94239396, 4.27729857, -89.90310912) + t * vec3(59.28637943, 2.82956604, 27.34824973)))));
    return clamp(c, 0.0, 1.0);
}
#ifdef DM_FRAGMENT /* the vertex stage: common.glsl's full-screen triangle */
in vec2 v_uv;
out vec4 o_color;
// Chart coverage at this texel: whether a triangle covers the fine texel under this texel's
// centre (the texture-space G-buffer's w, 0 or 1, rasterised; not the irradiance alpha, which
// the seam map makes 1 beyond the charts too).
float coverage(ivec2 ij)
{
    return texelFetch(u_cover, (ij << u_cov_shift) + ((1 << u_cov_shift) >> 1), 0).w;
}
void main()
{
    if (u_mode == 4) {
        o_color = texture(u_src, v_uv);
        return;
    }
    if (u_mode == 6) {
        ivec2 n = textureSize(u_src, 0);
        ivec2 at = min(ivec2(v_uv * vec2(n)), n - 1);
        vec4 t = texelFetch(u_src, at, 0);
        float s = u_stretch ? 1.0 / max(float(n.x) * sqrt(max(t.r * t.g, 0.0)), 1e-30) : t.r;
        bool ok = u_stretch ? t.r * t.g > 0.0 && (!u_has_mask || texture(u_mask, v_uv).r >= 0.5)
                : u_flagged ? t.g > 0.5 : !isnan(s);
        // the display readback sRGB-encodes: decode, so the picture shows the legend's colours
        vec3 c = turbo((s - u_lo) / max(u_hi - u_lo, 1e-30));
        c = mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), c));
        o_color = vec4(ok ? c : vec3(u_flagged && t.a > 0.5 ? 0.05 : 0.01), 1.0);
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
    } else if (u_mode == 7) {
        vec4 t = texelFetch(u_src, ij, 0);
        float taps = t.g + t.b; // the gather's index: (first, taps of level 0, of level 1, member)
        vec3 v = u_map_kind == 1 ? vec3(t.b, t.a, 0.0) : u_map_kind == 2 ? vec3(taps, taps > 0.0 ? 1.0 : 0.0, 0.0)
                                                                           : vec3(t.a, t.b, 0.0);
        o_color = vec4(v, coverage(ij)); // not scaled
        return;
    } else if (u_mode == 5) {
        c = vec3(texelFetch(u_src, ij, 0).r);
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
