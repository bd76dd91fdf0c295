// background.glsl - the environment behind the head: common.glsl's full-screen triangle at the
// far plane (depth test LEQUAL keeps the head), radiance looked up along each pixel's view ray.
// (dmr_screen_clear: with this pass in the plan the screen's colour is not cleared.)
uniform vec3 u_cam_forward; // forward, right * tan(fov/2) * aspect, up * tan(fov/2)
uniform vec3 u_cam_right;
uniform vec3 u_cam_up;
uniform float u_env_rotation;
uniform float u_env_intensity;
uniform sampler2D u_background;
#ifdef DM_FRAGMENT /* the vertex stage: common.glsl's full-screen triangle (at the far plane) */
in vec2 v_uv;
out vec4 o_color;
void main()
{
    vec2 ndc = v_uv * 2.0 - 1.0;
    vec3 d = normalize(u_cam_forward + ndc.x * u_cam_right + ndc.y * u_cam_up);
    // alpha 0: not skin (the screen's alpha is coverage); every pixel the head leaves is
    // written here, so the passes before need not clear the screen's colour
    o_color = vec4(u_env_intensity * texture(u_background, dm_equirect_uv(d, u_env_rotation)).rgb, 0.0);
}
#endif
