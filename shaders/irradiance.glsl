// irradiance.glsl - the mesh unwrapped into texture space: per texel, light arriving at the
// surface, pre-scatter albedo applied. Alpha is chart coverage (1 where a triangle covers the
// texel centre, cleared to 0 in gutters): the blurs treat rgb as premultiplied by it, so taps
// in gutters drop out and the kernel renormalises over the chart (seams do not darken).
// Defines: DM_ENERGY (1 - rho_s rho_dt), DM_ENV (SH diffuse), DM_TRANSLUCENCY (light through thin parts).
#ifdef DM_VERTEX
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_tangent;
layout(location = 3) in vec2 a_uv;
out vec3 v_pos;
out vec3 v_nrm;
out vec4 v_tan;
out vec2 v_uv;
void main()
{
    v_pos = a_position;
    v_nrm = a_normal;
    v_tan = a_tangent;
    v_uv = a_uv;
    gl_Position = vec4(a_uv * 2.0 - 1.0, 0.0, 1.0);
}
#else
in vec3 v_pos;
in vec3 v_nrm;
in vec4 v_tan;
in vec2 v_uv;
out vec4 o_color;
uniform sampler2D u_albedo;
uniform sampler2D u_normal_map;
uniform bool u_has_normal_map;
uniform sampler2D u_specular_map;
uniform sampler2D u_roughness_map;
uniform bool u_has_roughness_map;
uniform float u_roughness;
uniform float u_roughness_scale; // 1 = as given
uniform float u_rho_s;
uniform sampler2D u_rho_dt;
uniform vec3 u_sh[9];
uniform float u_env_intensity;
uniform float u_env_rotation;
uniform float u_mix;
void main()
{
    vec3 Ng = normalize(v_nrm);
    vec3 N = dm_shading_normal(v_nrm, v_tan, texture(u_normal_map, v_uv).rgb, u_has_normal_map);
    float m = min((u_has_roughness_map ? texture(u_roughness_map, v_uv).r : u_roughness) * u_roughness_scale, 1.0);
    float rho_s = u_rho_s * texture(u_specular_map, v_uv).r;
    vec3 e = vec3(0.0);
    for (int i = 0; i < DM_LIGHTS; ++i) {
        vec3 L = dm_light_dir(i, v_pos);
        float ndl = max(dot(N, L), 0.0);
        if (ndl <= 0.0) continue;
        float k = ndl * dm_shadow(i, v_pos, Ng);
#ifdef DM_ENERGY
        k *= max(1.0 - rho_s * texture(u_rho_dt, vec2(ndl, m)).r, 0.0);
#endif
        e += u_light_color[i] * k;
    }
#ifdef DM_TRANSLUCENCY
    e += dm_translucency(v_pos, Ng);
#endif
#ifdef DM_ENV
    e += u_env_intensity * dm_sh_irradiance(u_sh, dm_env_rotate(N, u_env_rotation)) / DM_PI;
#endif
    vec3 albedo = texture(u_albedo, v_uv).rgb;
    o_color = vec4(e * pow(max(albedo, vec3(0.0)), vec3(u_mix)), 1.0);
}
#endif
