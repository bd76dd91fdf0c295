// final.glsl - the head on screen. Diffuse: with DM_SUBSURFACE the blur levels weighted per
// channel and renormalised (coverage-normalised: rgb / alpha; dm_diffusion in common.glsl), times post-scatter
// albedo^(1 - mix); without it Lambert from the lights (and SH) times albedo. DM_SPECULAR: KS
// specular per light. DM_ENERGY: diffuse x (1 - rho_s rho_dt(N.V)). DM_ENV: SH diffuse (when no
// subsurface) and, with DM_SPECULAR, split-sum environment specular.
// u_mode: 0 final, 1 specular only, 2 diffuse only, 3 UV checker, 4 wireframe.
// DM_SCREEN_SPACE (the ss_shade pass, lib/render/passes/dm_pass_ssss.c): three outputs instead of the
// sum: o_color = diffuse irradiance x albedo^mix with alpha = eye depth (mesh units), o_aux =
// post-scatter factor albedo^(1-mix) (x energy out), o_spec = specular. DM_TRANSLUCENCY: light
// through thin parts joins the diffuse irradiance (without texture-space subsurface; with it,
// the irradiance pass adds it). DM_PRE_INTEGRATED (lib/render/passes/dm_pass_preint.c): each light's
// diffuse from the table D(N.L, curvature) per channel instead of N.L.
// DM_GBUFFER (the gbuffer pass): the head's surface (position and uv, geometric and shading
// normal, albedo, rho_s, roughness; the maps read here, at the mip level rasterising gives)
// into four float targets instead of shading. DM_DEFERRED (the final or ss_shade pass after
// it): common.glsl's full-screen triangle, each head pixel shaded from those targets: the same
// values, bit for bit, so the same picture as shading while rasterising, but with every SIMD
// lane on a pixel (llvmpipe shades 4x4 blocks: along the edges of the head's ~30-pixel
// triangles most lanes of the expensive lighting were masked off). Without either (the uv and
// wireframe views) the mesh is drawn and shaded directly. Every pixel is shaded at its point
// lifted to the smooth surface (dm_smooth_point, common.glsl): the G-buffer holds that point.
uniform mat4 u_view_proj;
#if defined(DM_VERTEX) && !defined(DM_DEFERRED)
void main()
{
    dm_mesh_vertex(u_view_proj * vec4(a_position, 1.0));
}
#elif defined(DM_FRAGMENT)
#ifdef DM_DEFERRED /* G-buffer: position (lifted: dm_smooth_point), u | geometric normal, v | shading normal, rho_s | albedo, m */
vec2 v_uv;
#else
in vec3 v_pos;
in vec3 v_nrm;
in vec4 v_tan;
in vec2 v_uv;
in float v_pn;
#endif
#ifndef DM_GBUFFER
layout(location = 0) out vec4 o_color;
#endif
#ifdef DM_SCREEN_SPACE
#ifndef DM_GBUFFER
layout(location = 1) out vec4 o_aux;
layout(location = 2) out vec4 o_spec;
#endif
uniform vec3 u_cam_forward;
#endif
uniform int u_mode;
uniform vec3 u_eye;
uniform sampler2D u_beckmann;
uniform sampler2D u_rho_dt;
uniform sampler2D u_env_brdf; /* R = scale, G = bias of F0 */
uniform vec3 u_sh[9];
uniform float u_env_intensity;
uniform float u_env_rotation;
uniform float u_env_level_m[6];
uniform sampler2D u_env_level[6];
uniform sampler2DArray u_env_array; // the same levels as layers (DM_ENV_ARRAY: all one size)
uniform float u_mix;
#ifdef DM_PRE_INTEGRATED
uniform sampler2D u_preint;    // D(N.L, curvature): s = (N.L + 1)/2 at texel centres
uniform sampler2D u_curvature; // mean curvature, 1/mm (negative: concave)
uniform float u_preint_kmax;   // curvature of the table's last row; row j = kmax j/(height-1)
uniform float u_preint_height;
uniform vec3 u_preint_blend;   // per channel: how far its normal bends from the map's to the geometric
#endif
vec3 env_level(int k, vec2 uv)
{
    if (k == 0) return texture(u_env_level[0], uv).rgb;
    if (k == 1) return texture(u_env_level[1], uv).rgb;
    if (k == 2) return texture(u_env_level[2], uv).rgb;
    if (k == 3) return texture(u_env_level[3], uv).rgb;
    if (k == 4) return texture(u_env_level[4], uv).rgb;
    return texture(u_env_level[5], uv).rgb;
}

// Prefiltered radiance for roughness m: linear between the two levels around m.
vec3 env_specular(vec3 R, float m)
{
    vec2 uv = dm_equirect_uv(R, u_env_rotation);
    const int n = DM_ENV_LEVELS;
#ifdef DM_ENV_ARRAY
    // The same choice as below, made in arithmetic, then two layer fetches: llvmpipe runs every
    // branch, so the if-chains below cost every level's fetch several times over.
    if (n <= 0) return vec3(0.0);
    float lo = 0.0, t = 0.0;
    for (int k = 1; k < n; ++k)
        if (m > u_env_level_m[k - 1]) {
            lo = float(k - 1);
            t = (m - u_env_level_m[k - 1]) / max(u_env_level_m[k] - u_env_level_m[k - 1], 1e-6);
        }
    if (m > u_env_level_m[n - 1]) {
        lo = float(n - 1);
        t = 0.0;
    }
    return mix(texture(u_env_array, vec3(uv, lo)).rgb, texture(u_env_array, vec3(uv, min(lo + 1.0, float(n - 1)))).rgb,
               t);
#endif
    if (n <= 0) return vec3(0.0);
    if (m <= u_env_level_m[0] || n == 1) return env_level(0, uv);
    for (int k = 1; k < n; ++k)
        if (m <= u_env_level_m[k]) {
            float t = (m - u_env_level_m[k - 1]) / max(u_env_level_m[k] - u_env_level_m[k - 1], 1e-6);
            return mix(env_level(k - 1, uv), env_level(k, uv), t);
        }
    return env_level(n - 1, uv);
}

void main()
{
#ifdef DM_DEFERRED
    ivec2 q = ivec2(gl_FragCoord.xy);
    vec4 g0 = texelFetch(u_gbuf0, q, 0), g1 = texelFetch(u_gbuf1, q, 0);
    vec3 P = g0.xyz;
    v_uv = vec2(g0.w, g1.w);
    vec3 Ng = g1.xyz;
    vec4 g2 = texelFetch(u_gbuf2, q, 0), g3 = texelFetch(u_gbuf3, q, 0);
    vec3 N = g2.xyz, albedo = g3.rgb;
    float rho_s = g2.w, m = g3.w;
#else
#ifndef DM_GBUFFER
    if (u_mode == 4) {
        o_color = vec4(1.0);
        return;
    }
    if (u_mode == 3) {
        vec2 c = floor(v_uv * 16.0);
        float check = mod(c.x + c.y, 2.0);
        o_color = vec4(mix(vec3(0.1), vec3(0.9), check) * vec3(v_uv, 1.0 - v_uv.x * 0.5), 1.0);
        return;
    }
#endif
    dm_surf s = dm_surface(v_nrm, v_tan, v_uv); // common.glsl
    vec3 P = dm_smooth_point(v_pos, v_nrm, v_pn), Ng = s.Ng, N = s.N, albedo = max(s.albedo, vec3(0.0));
    float m = min(s.m0 * u_roughness_scale, 1.0), rho_s = s.rho_s;
#endif
#ifdef DM_GBUFFER
    o_g0 = vec4(P, v_uv.x);
    o_g1 = vec4(Ng, v_uv.y);
    o_g2 = vec4(N, rho_s);
    o_g3 = vec4(albedo, m);
    return;
#else
    vec3 V = normalize(u_eye - P);
    float ndv = max(dot(N, V), 0.0);

    vec3 diffuse = vec3(0.0), specular = vec3(0.0);
#ifdef DM_SUBSURFACE
    diffuse = dm_diffusion(v_uv) * pow(albedo, vec3(1.0 - u_mix)); // common.glsl
#else
    vec3 e = vec3(0.0);
#ifdef DM_PRE_INTEGRATED
    float kappa = clamp(texture(u_curvature, v_uv).r, 0.0, u_preint_kmax);
    float pt = (0.5 + (u_preint_height - 1.0) * kappa / u_preint_kmax) / u_preint_height;
    vec3 NR = normalize(mix(N, Ng, u_preint_blend.r)), NG = normalize(mix(N, Ng, u_preint_blend.g)),
         NB = normalize(mix(N, Ng, u_preint_blend.b));
#endif
    for (int i = 0; i < DM_LIGHTS; ++i) {
        vec3 L = dm_light_dir(i, P);
        float ndl = max(dot(N, L), 0.0);
#ifdef DM_PRE_INTEGRATED
        vec3 d = vec3(texture(u_preint, vec2(0.5 * dot(NR, L) + 0.5, pt)).r,
                      texture(u_preint, vec2(0.5 * dot(NG, L) + 0.5, pt)).g,
                      texture(u_preint, vec2(0.5 * dot(NB, L) + 0.5, pt)).b);
        // Lambert's part takes the shadow; what the blur moves past the terminator (d - lam) only
        // where Ng.L > 0.2, since a shadow map shadows every point facing away from its light.
        vec3 lam = max(vec3(dot(NR, L), dot(NG, L), dot(NB, L)), 0.0);
        float sh = dm_shadow(i, P, Ng);
        vec3 kp = max(lam * sh + (d - lam) * mix(1.0, sh, smoothstep(0.0, 0.2, dot(Ng, L))), 0.0);
#ifdef DM_ENERGY
        kp *= max(1.0 - rho_s * texture(u_rho_dt, vec2(ndl, m)).r, 0.0);
#endif
        e += u_light_color[i] * kp;
#else
        // no `continue` where N.L = 0 (k = 0, KS = 0: the same sums): see irradiance.glsl
#if defined(DM_SCREEN_SPACE) && defined(DM_SPECULAR)
        // one shadow lookup for both terms (the texture-space and Lambert paths keep their two loops)
        float sh = dm_shadow(i, P, Ng);
        float k = ndl * sh;
        specular += u_light_color[i] * (sh * dm_ks_specular(u_beckmann, N, L, V, m, rho_s));
#else
        float k = ndl * dm_shadow(i, P, Ng);
#endif
#ifdef DM_ENERGY
        k *= max(1.0 - rho_s * texture(u_rho_dt, vec2(ndl, m)).r, 0.0);
#endif
        e += u_light_color[i] * k;
#endif
    }
#ifdef DM_TRANSLUCENCY
    e += dm_translucency(P, Ng);
#endif
#ifdef DM_ENV
    e += u_env_intensity * dm_sh_irradiance(u_sh, dm_env_rotate(N, u_env_rotation)) / DM_PI;
#endif
#ifdef DM_SCREEN_SPACE
    vec3 pre = e * pow(albedo, vec3(u_mix)), post = pow(albedo, vec3(1.0 - u_mix));
#else
    diffuse = e * albedo;
#endif
#endif
#ifdef DM_ENERGY
#ifdef DM_SCREEN_SPACE
    post *= max(1.0 - rho_s * texture(u_rho_dt, vec2(ndv, m)).r, 0.0);
#else
    diffuse *= max(1.0 - rho_s * texture(u_rho_dt, vec2(ndv, m)).r, 0.0);
#endif
#endif
#ifdef DM_SPECULAR
#ifndef DM_SCREEN_SPACE /* screen space: summed in the diffuse loop above */
    for (int i = 0; i < DM_LIGHTS; ++i) {
        vec3 L = dm_light_dir(i, P); // KS is 0 where N.L <= 0 (no `continue`: irradiance.glsl)
        specular += u_light_color[i] * (dm_shadow(i, P, Ng) * dm_ks_specular(u_beckmann, N, L, V, m, rho_s));
    }
#endif
#ifdef DM_ENV
    vec3 R = reflect(-V, N);
    vec2 scale_bias = texture(u_env_brdf, vec2(ndv, m)).rg;
    float split = DM_SKIN_F0 * scale_bias.r + scale_bias.g;
    specular += u_env_intensity * rho_s * split * env_specular(R, m);
#endif
#endif
#ifdef DM_SCREEN_SPACE
    o_color = vec4(pre, max(dot(P - u_eye, u_cam_forward), 1e-6));
    o_aux = vec4(post, 1.0);
    o_spec = vec4(specular, 1.0);
    return;
#endif
    vec3 c = u_mode == 1 ? specular : u_mode == 2 ? diffuse : diffuse + specular;
    o_color = vec4(c, 1.0);
#endif
}
#endif
