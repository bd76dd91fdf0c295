// seam_mark.glsl - once per scene, after the texture-space G-buffer: the gutter texels the seam
// map continues (bake/dm_seam_map.h) take the coverage depth, 0.5, so that the irradiance pass,
// which tests GREATER against it, lights them as it lights covered texels (and skips every
// other gutter texel as before). Colour writes are off: the G-buffer keeps 0 there.
uniform sampler2D u_seam;
#ifdef DM_FRAGMENT /* the vertex stage: common.glsl's full-screen triangle */
in vec2 v_uv;
out vec4 o_color;
void main()
{
    if (texture(u_seam, v_uv).z == 0.0) discard; // once per scene: the discard costs nothing here
    gl_FragDepth = 0.5;
    o_color = vec4(0.0);
}
#endif
