// ss_blur.glsl - one pass of the screen-space separable subsurface blur (Jimenez et al. 2015;
// lib/render/passes/dm_pass_ssss.c). u_src: rgb = diffuse irradiance x albedo^mix, a = eye depth in
// mesh units (0: no skin). The kernel has a row per size of pixel (core/dm_ssss_kernel.h), its
// offsets in pixels at the row's size (whole pixels near the centre, so a fetch reads one pixel):
// the pixel's size, depth / u_px_per_mm mm, gives its row coordinate u = log2(depth) u_row.x +
// u_row.y, and the taps are those of the rows around it, interpolated; off the table's ends the
// end row's offsets are stretched by the sizes' ratio (as a kernel in mm; a table of one row,
// from a pack made before the rows, is always so). Follow-surface: a tap whose depth differs from the centre's by more than
// its lateral distance fades to the centre's value (fully at twice it), so nothing bleeds
// across silhouettes and the weights still sum to 1. common.glsl's full-screen triangle sits
// at the far plane and the depth test (GREATER) keeps it to skin pixels.
// The H pass: out = (blurred, depth); the V pass (DM_SS_COMBINE, a define, not a uniform:
// llvmpipe would run both sides, the H pass fetching u_aux and u_spec too): out = blurred x
// u_aux + u_spec (u_mode 1: specular only, 2: diffuse only), alpha 1.
uniform sampler2D u_src;
uniform sampler2D u_aux;
uniform sampler2D u_spec;
uniform vec2 u_dir;
uniform vec2 u_texel;
uniform vec4 u_kernel[DM_SS_TAPS * DM_SS_ROWS]; // row after row: rgb weight, a = offset px
uniform float u_px_per_mm;                       // pixels per mm at eye depth 1 mesh unit
uniform vec2 u_row;                              // row coordinate = log2(depth) x + y
uniform float u_ss_mm_per_unit;
uniform int u_mode;
#ifdef DM_FRAGMENT /* the vertex stage: common.glsl's full-screen triangle (at the far plane) */
in vec2 v_uv;
out vec4 o_color;
void main()
{
    // the pixel's own texels read exactly (a bilinear tap at the interpolated centre would
    // mix in ~1e-4 of a neighbour: across a silhouette, of the background's depth 0)
    ivec2 q = ivec2(gl_FragCoord.xy);
    vec4 c = texelFetch(u_src, q, 0);
    vec3 sum = vec3(0.0);
    if (c.a > 0.0) {
        float mm_per_px = c.a / u_px_per_mm;
        float u = log2(c.a) * u_row.x + u_row.y;
        float uc = clamp(u, 0.0, float(DM_SS_ROWS - 1));
        float stretch = exp2((uc - u) / u_row.x); // 1 within the table
        int r0 = min(int(uc), DM_SS_ROWS - 1) * DM_SS_TAPS;
        int r1 = min(int(uc) + 1, DM_SS_ROWS - 1) * DM_SS_TAPS;
        float f = uc - floor(uc);
        for (int i = 0; i < DM_SS_TAPS; ++i) {
            vec4 k = mix(u_kernel[r0 + i], u_kernel[r1 + i], f);
            float o_px = k.a * stretch, o_mm = o_px * mm_per_px;
            vec4 t = texture(u_src, v_uv + u_dir * o_px * u_texel);
            float dz_mm = abs(t.a - c.a) * u_ss_mm_per_unit;
            float s = t.a > 0.0 ? clamp(dz_mm / (abs(o_mm) + 1e-3) - 1.0, 0.0, 1.0) : 1.0;
            sum += k.rgb * mix(t.rgb, c.rgb, s);
        }
    }
#ifndef DM_SS_COMBINE
    o_color = vec4(sum, c.a);
#else
    vec3 diffuse = u_mode == 1 ? vec3(0.0) : sum * texelFetch(u_aux, q, 0).rgb;
    vec3 spec = u_mode == 2 ? vec3(0.0) : texelFetch(u_spec, q, 0).rgb;
    o_color = vec4(diffuse + spec, c.a > 0.0 ? 1.0 : 0.0);
#endif
}
#endif
