// seam_points.glsl - once per scene, after seam_mark.glsl: each texel's 3-D point in mm as the
// irradiance pass lights it - a covered texel its own (the texture-space G-buffer's), a gutter
// texel the seam map continues the point where the surface goes on (irradiance.glsl's DM_SEAM) -
// and w = that texel's coverage (0: no point). The blurs read it (blur.glsl, the CPU's
// core/dm_level_blur.h) to leave out the taps that land on another place of the surface.
uniform sampler2D u_gbuf0;
uniform sampler2D u_seam;
uniform float u_mm; // mm per mesh unit
#ifdef DM_FRAGMENT /* the vertex stage: common.glsl's full-screen triangle */
out vec4 o_color;
void main()
{
    ivec2 q = ivec2(gl_FragCoord.xy);
    if (texelFetch(u_gbuf0, q, 0).w == 0.0) {
        vec2 edge = vec2(textureSize(u_gbuf0, 0));
        vec4 s = texture(u_seam, (vec2(q) + 0.5) / edge);
        if (s.z == 0.0) {
            // a gutter texel the seam map does not continue takes the point of the nearest
            // covered texel within 2 (the first in row order among the nearest): the blurs
            // spread its chart's light into it, so it stands for that chart
            ivec2 best = ivec2(-1);
            int d2 = 9;
            for (int dy = -2; dy <= 2; ++dy)
                for (int dx = -2; dx <= 2; ++dx) {
                    ivec2 j = q + ivec2(dx, dy);
                    if (any(lessThan(j, ivec2(0))) || any(greaterThanEqual(j, ivec2(edge)))) continue;
                    if (dx * dx + dy * dy < d2 && texelFetch(u_gbuf0, j, 0).w > 0.0) {
                        d2 = dx * dx + dy * dy;
                        best = j;
                    }
                }
            if (best.x < 0) {
                o_color = vec4(0.0);
                return;
            }
            q = best;
        } else {
            q = ivec2(floor(s.xy * edge));
        }
    }
    vec4 g = texelFetch(u_gbuf0, q, 0);
    o_color = vec4(g.xyz * u_mm, g.w);
}
#endif
