// view.glsl - debug view of a texture-space intermediate, stretched over the screen.
// u_mode: 0 premultiplied level (rgb / alpha), 1 stretch (u red, v green, mask blue),
// 2 shadow depth. Values x u_scale, no tonemap.
uniform int u_mode;
uniform float u_scale;
uniform sampler2D u_src;
uniform sampler2D u_mask;
uniform bool u_has_mask;
uniform sampler2D u_depth;
#ifdef DM_VERTEX
out vec2 v_uv;
void main()
{
    gl_Position = dm_fullscreen(v_uv);
}
#else
in vec2 v_uv;
out vec4 o_color;
void main()
{
    vec3 c;
    if (u_mode == 0) {
        vec4 t = texture(u_src, v_uv);
        c = t.a > 1e-4 ? t.rgb / t.a : vec3(0.0);
    } else if (u_mode == 1) {
        c = vec3(texture(u_src, v_uv).rg, u_has_mask ? texture(u_mask, v_uv).r : 0.0);
    } else {
        c = vec3(texture(u_depth, v_uv).r);
    }
    o_color = vec4(c * u_scale, 1.0);
}
#endif
