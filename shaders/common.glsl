// common.glsl - prepended to every pass (after #version and the DM_* defines).
// Shared functions and the light uniforms; GLSL has no #include, the loader
// (lib/render/frame/dm_frame_program.c) concatenates: version, stage + effect defines, this, the pass.
const float DM_PI = 3.14159265358979;
const float DM_SKIN_F0 = 0.028;
const int DM_MAX_LIGHTS = 8;

#ifdef DM_VERTEX
// A triangle covering the screen from gl_VertexID 0..2 (no vertex buffer); uv in [0, 1].
vec4 dm_fullscreen(out vec2 uv)
{
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    uv = p;
    return vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
#ifdef DM_FULLSCREEN
// The whole vertex stage of a pass file that has none (the loader defines DM_FULLSCREEN for
// it): the full-screen triangle, uv to the fragment stage as v_uv. It sits at the far plane:
// passes that test GREATER against the head's depth (the screen-space blurs, the tonemap)
// shade only the head's pixels; without a depth test its depth does not matter.
out vec2 v_uv;
void main()
{
    gl_Position = dm_fullscreen(v_uv);
    gl_Position.z = gl_Position.w;
}
#endif
#ifdef DM_MESH_VERTEX
// The vertex stage's inputs and outputs in the passes that rasterise the head's mesh (the
// loader defines DM_MESH_VERTEX for a pass file that calls dm_mesh_vertex): its attributes go
// to the fragment stage as they are, at the clip position the pass gives, with v_pn =
// position . normal for dm_smooth_point.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_tangent;
layout(location = 3) in vec2 a_uv;
out vec3 v_pos;
out vec3 v_nrm;
out vec4 v_tan;
out vec2 v_uv;
out float v_pn;
void dm_mesh_vertex(vec4 clip)
{
    v_pos = a_position;
    v_pn = dot(a_position, a_normal);
    v_nrm = a_normal;
    v_tan = a_tangent;
    v_uv = a_uv;
    gl_Position = clip;
}
#endif
#endif

#if defined(DM_FRAGMENT) && defined(DM_GBUFFER)
// Deferred shading (dmr_gbuffer_targets): a pass compiled with DM_GBUFFER writes the surface
// into four float targets, one compiled with DM_DEFERRED reads them back per pixel; the pass
// file says what each holds.
layout(location = 0) out vec4 o_g0;
layout(location = 1) out vec4 o_g1;
layout(location = 2) out vec4 o_g2;
layout(location = 3) out vec4 o_g3;
#elif defined(DM_FRAGMENT) && defined(DM_DEFERRED)
uniform sampler2D u_gbuf0;
uniform sampler2D u_gbuf1;
uniform sampler2D u_gbuf2;
uniform sampler2D u_gbuf3;
#endif

#ifdef DM_FRAGMENT
// The point where the mesh's passes shade a fragment: its flat facet's point P lifted towards
// the smooth surface the vertex normals describe (issue #27), as the ground truth starts its
// shadow rays (dm_ref_surface_smooth_point): along the normal by half the depth of P below the
// corners' tangent planes weighted by its barycentrics, sum_k b_k (p_k - P).n_k (clamped as a
// sum, not per corner as the ground truth does), nothing where the sum is negative (concave:
// P above them). nrm and pn are the interpolated vertex normal, unnormalised, and v_pn
// (p_k . n_k), so the sum is pn - P.nrm. A shadow map holds the flat facets, up to the sagitta below the smooth
// surface: looked up from P, the facets next to a lit point shadow it along the terminator.
vec3 dm_smooth_point(vec3 P, vec3 nrm, float pn)
{
    return P + normalize(nrm) * max(0.5 * (pn - dot(P, nrm)), 0.0);
}

// Texture-space diffusion levels (irradiance = level 0, blur k = level k), premultiplied by
// chart coverage in alpha. One copy for the final pass and the diffusion view, so the view
// is exactly the sum the final pass samples.
uniform vec3 u_level_weight[8]; // per channel, already divided by their sum
uniform sampler2D u_level[8]; /* DM_PROFILE_MAX_GAUSSIANS levels */

// Level k at uv, coverage-normalised (rgb / alpha; 0 where nothing covers).
vec3 dm_level(int k, vec2 uv)
{
    vec4 t = vec4(0.0);
    // GLSL 3.30 indexes sampler arrays by constants only.
    if (k == 0) t = texture(u_level[0], uv);
    else if (k == 1) t = texture(u_level[1], uv);
    else if (k == 2) t = texture(u_level[2], uv);
    else if (k == 3) t = texture(u_level[3], uv);
    else if (k == 4) t = texture(u_level[4], uv);
    else if (k == 5) t = texture(u_level[5], uv);
    else if (k == 6) t = texture(u_level[6], uv);
    else t = texture(u_level[7], uv);
    return t.a > 1e-4 ? t.rgb / t.a : vec3(0.0);
}

// The diffused radiance sum_k w_k L_k over the DM_LEVELS levels, each level sampled at uv.
vec3 dm_level_sum(vec2 uv)
{
    vec3 sum = vec3(0.0);
    for (int k = 0; k < DM_LEVELS; ++k) sum += u_level_weight[k] * dm_level(k, uv);
    return sum;
}

#if defined(DM_DIFFUSION_SUM) && !defined(DM_DIFFUSION_PASS)
// DM_DIFFUSION_SUM: the diffusion pass (diffusion.glsl) made that sum once per texel, in
// texture space, times chart coverage, alpha = coverage; read here with one bilinear fetch,
// coverage-normalised like a level, instead of DM_LEVELS fetches per pixel.
uniform sampler2D u_diffusion;
vec3 dm_diffusion(vec2 uv)
{
    vec4 t = texture(u_diffusion, uv);
    return t.a > 1e-4 ? t.rgb / t.a : vec3(0.0);
}
#else
vec3 dm_diffusion(vec2 uv)
{
    return dm_level_sum(uv);
}
#endif
#endif

vec3 dm_srgb_encode(vec3 c)
{
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

// Beckmann D from the 8-bit LUT (s = N.H, t = m), decoded as (2 tex)^10 (DESIGN.md).
float dm_beckmann_lut(sampler2D lut, float ndh, float m)
{
    float t = texture(lut, vec2(clamp(ndh, 0.0, 1.0), clamp(m, 0.0, 1.0))).r;
    return pow(2.0 * t, 10.0);
}

float dm_fresnel_schlick(float c, float f0)
{
    float b = 1.0 - clamp(c, 0.0, 1.0);
    float b2 = b * b;
    return f0 + (1.0 - f0) * b2 * b2 * b;
}

// KS specular factor (N.L) rho_s max(D F / |h|^2, 0); zero when N.L <= 0 or L = -V.
float dm_ks_specular(sampler2D lut, vec3 N, vec3 L, vec3 V, float m, float rho_s)
{
    float ndl = dot(N, L);
    if (ndl <= 0.0) return 0.0;
    vec3 h = L + V;
    float hh = dot(h, h);
    if (hh < 1e-8) return 0.0;
    vec3 H = h * inversesqrt(hh);
    float D = dm_beckmann_lut(lut, dot(N, H), m);
    float F = dm_fresnel_schlick(dot(H, V), DM_SKIN_F0);
    return ndl * rho_s * max(D * F / hh, 0.0);
}

// Irradiance from radiance SH (Ramamoorthi & Hanrahan 2001); a constant radiance L gives pi L.
vec3 dm_sh_irradiance(vec3 sh[9], vec3 n)
{
    const float c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708;
    float x = n.x, y = n.y, z = n.z;
    vec3 e = c1 * sh[8] * (x * x - y * y) + c3 * sh[6] * z * z + c4 * sh[0] - c5 * sh[6] +
             2.0 * c1 * (sh[4] * x * y + sh[7] * x * z + sh[5] * y * z) +
             2.0 * c2 * (sh[3] * x + sh[1] * y + sh[2] * z);
    return max(e, vec3(0.0));
}

// Equirect coordinates of direction d (mesh space) for an environment turned by rot (radians,
// about +Y): u = 0.5 + atan2(x, -z)/2pi, v = 0.5 + asin(y)/pi (v = 1 straight up).
vec2 dm_equirect_uv(vec3 d, float rot)
{
    float c = cos(rot), s = sin(rot);
    vec3 r = vec3(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
    return vec2(0.5 + atan(r.x, -r.z) / (2.0 * DM_PI), 0.5 + asin(clamp(r.y, -1.0, 1.0)) / DM_PI);
}

// The same turn applied to a normal before SH evaluation.
vec3 dm_env_rotate(vec3 d, float rot)
{
    float c = cos(rot), s = sin(rot);
    return vec3(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
}

// Shading normal from a tangent-space map (green up); flat (0, 0, 1) without one.
vec3 dm_shading_normal(vec3 n, vec4 t, vec3 map_rgb, bool has_map)
{
    vec3 N = normalize(n);
    if (!has_map) return N;
    vec3 T = t.xyz - N * dot(N, t.xyz);
    float tl = dot(T, T);
    if (tl < 1e-12) return N;
    T *= inversesqrt(tl);
    vec3 B = (t.w < 0.0 ? -1.0 : 1.0) * cross(N, T);
    vec3 m = map_rgb * 2.0 - 1.0;
    vec3 r = T * m.x + B * m.y + N * m.z;
    float rl = dot(r, r);
    return rl > 1e-12 ? r * inversesqrt(rl) : N;
}

#ifdef DM_FRAGMENT
// The surface as the maps give it where a pass rasterises the mesh (final.glsl, irradiance.glsl:
// shading directly or into a G-buffer): geometric and shading normal, albedo, roughness m0
// before the frame's scale, rho_s. DM_SPEC_IN_NORMAL: the specular map rides in the normal
// map's alpha (dm_render.c). Read with implicit derivatives, so the mip level rasterising gives.
uniform sampler2D u_albedo;
uniform sampler2D u_normal_map;   // DM_NORMAL_MAP: there is one
uniform sampler2D u_specular_map;
uniform sampler2D u_roughness_map; // DM_ROUGHNESS_MAP: there is one (else u_roughness)
uniform float u_roughness;
uniform float u_roughness_scale; // 1 = as given
uniform float u_rho_s;
struct dm_surf {
    vec3 Ng, N, albedo;
    float m0, rho_s;
};
dm_surf dm_surface(vec3 nrm, vec4 tan, vec2 uv)
{
    dm_surf s;
    s.Ng = normalize(nrm);
    vec4 nmap = texture(u_normal_map, uv);
#ifdef DM_NORMAL_MAP
    s.N = dm_shading_normal(nrm, tan, nmap.rgb, true);
#else
    s.N = dm_shading_normal(nrm, tan, nmap.rgb, false);
#endif
#ifdef DM_ROUGHNESS_MAP
    s.m0 = texture(u_roughness_map, uv).r;
#else
    s.m0 = u_roughness;
#endif
#ifdef DM_SPEC_IN_NORMAL
    s.rho_s = u_rho_s * nmap.a;
#else
    s.rho_s = u_rho_s * texture(u_specular_map, uv).r;
#endif
    s.albedo = texture(u_albedo, uv).rgb;
    return s;
}
#endif

// DM_LIGHTS (light count), DM_SHADOW_MAPS, DM_TAPS, DM_LEVELS, DM_ENV_LEVELS are defined by the loader: loops
// with constant bounds unroll (llvmpipe runs dynamic loops several times slower; a loop that
// `continue`s is not unrolled). So are the lights' fixed facts, DM_LIGHT_SHADOW(i) (light i's
// shadow map, -1: none), DM_LIGHT_POINT(i) and DM_SHADOW_LIGHT(j) (shadow map j's light): in an
// unrolled loop they are constants, and no branch depends on a uniform (llvmpipe runs both
// sides of one: every light paid for the shadow lookup).
// Lights: xyz = direction towards the light (w = 0) or position (w = 1); colour x intensity.
uniform vec4 u_light_pos[DM_MAX_LIGHTS];
uniform vec3 u_light_color[DM_MAX_LIGHTS];
uniform mat4 u_light_matrix[DM_MAX_LIGHTS]; // mesh space -> shadow clip space
uniform float u_shadow_normal_offset;       // mesh units
uniform float u_shadow_texel;               // 1 / shadow map size
// Four 2D shadow maps, not one array: llvmpipe samples sampler2DArrayShadow ~4x slower.
uniform sampler2DShadow u_shadow0;
uniform sampler2DShadow u_shadow1;
uniform sampler2DShadow u_shadow2;
uniform sampler2DShadow u_shadow3;

// GLSL 3.30 indexes samplers by constants only: choose the map by a (uniform) branch, and
// only among the DM_SHADOW_MAPS that exist (llvmpipe runs masked branches anyway).
float dm_shadow_tap(int map, vec3 p)
{
#if DM_SHADOW_MAPS > 1
    if (map == 1) return texture(u_shadow1, p);
#endif
#if DM_SHADOW_MAPS > 2
    if (map == 2) return texture(u_shadow2, p);
#endif
#if DM_SHADOW_MAPS > 3
    if (map == 3) return texture(u_shadow3, p);
#endif
    return texture(u_shadow0, p);
}

vec3 dm_light_dir(int i, vec3 P)
{
    vec4 l = u_light_pos[i];
    if (DM_LIGHT_POINT(i) == 0) return normalize(l.xyz);
    vec3 d = l.xyz - P;
    float dl = dot(d, d);
    return dl > 1e-20 ? d * inversesqrt(dl) : vec3(0.0, 0.0, 1.0);
}

// 3x3 PCF over the hardware-compared (bilinear) shadow map: 1 lit, 0 shadowed.
// Nine bilinear taps one texel apart weigh the 4x4 texels around p by (1-f, 1, 1, f) per axis
// (f = the bilinear fraction), /9. DM_SHADOW_TAPS 4 takes the same sum with four bilinear taps
// (Castano's optimised PCF): texels 0,1 weigh (1-f, 1) = (2-f) x bilinear at fraction
// 1/(2-f), texels 2,3 weigh (1, f) = (1+f) x bilinear at fraction f/(1+f): the same filter up
// to float rounding, at 4 compares instead of 9 (llvmpipe runs every tap: no branch skips).
// DM_SHADOW_TAPS 1 is a single bilinear compare (2x2 texels; a quality setting, not exact).
float dm_shadow(int i, vec3 P, vec3 Ng)
{
#if DM_SHADOW_MAPS == 0
    return 1.0;
#else
    int layer = DM_LIGHT_SHADOW(i);
    if (layer < 0) return 1.0;
    vec4 c = u_light_matrix[i] * vec4(P + Ng * u_shadow_normal_offset, 1.0);
    vec3 p = c.xyz / c.w * 0.5 + 0.5;
    if (p.x < 0.0 || p.x > 1.0 || p.y < 0.0 || p.y > 1.0 || p.z > 1.0) return 1.0;
#if DM_SHADOW_TAPS == 9
    float s = 0.0;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x)
            s += dm_shadow_tap(layer, vec3(p.xy + vec2(x, y) * u_shadow_texel, p.z));
    return s / 9.0;
#elif DM_SHADOW_TAPS == 4
    vec2 t = p.xy / u_shadow_texel - 0.5; // texel space, texel centres at integers
    vec2 i0 = floor(t), f = t - i0;
    vec2 wa = 2.0 - f, wb = 1.0 + f;  // weights of the pairs (i0-1, i0) and (i0+1, i0+2)
    vec2 ca = i0 - 1.0 + 1.0 / wa;    // bilinear positions giving those pairs' inner weights
    vec2 cb = i0 + 1.0 + f / wb;
    ca = (ca + 0.5) * u_shadow_texel;
    cb = (cb + 0.5) * u_shadow_texel;
    float s = wa.x * wa.y * dm_shadow_tap(layer, vec3(ca.x, ca.y, p.z)) +
              wb.x * wa.y * dm_shadow_tap(layer, vec3(cb.x, ca.y, p.z)) +
              wa.x * wb.y * dm_shadow_tap(layer, vec3(ca.x, cb.y, p.z)) +
              wb.x * wb.y * dm_shadow_tap(layer, vec3(cb.x, cb.y, p.z));
    return s / 9.0;
#else
    return dm_shadow_tap(layer, p);
#endif
#endif
}

#if defined(DM_TRANSLUCENCY) && defined(DM_FRAGMENT)
// Translucency (lib/render/passes/dm_pass_translucency.c, Jimenez et al. 2010): light C I T(d)
// max(-Ng.L, 0) through thickness d (mm) between the point, shrunk inward along Ng, and the
// first surface the light's depth map holds; T(d) = sum_k w_k exp(-d^2 / 2 v_k).
uniform sampler2D u_tdepth0; // the shadow maps' raw depths (sampler object, no compare)
uniform sampler2D u_tdepth1;
uniform sampler2D u_tdepth2;
uniform sampler2D u_tdepth3;
uniform vec4 u_light_depth[DM_MAX_LIGHTS]; // near, far (mesh units), z = 1: orthographic
uniform float u_trans_var[DM_TRANS_GAUSSIANS];   // -log2(e) / (2 v_k), v_k in mm^2: exp2(d^2 x) = exp(-d^2/2v_k)
uniform vec3 u_trans_weight[DM_TRANS_GAUSSIANS]; // per channel, summing to 1
uniform float u_mm_per_unit;
uniform float u_translucency;

float dm_tdepth(int map, vec2 uv)
{
#if DM_SHADOW_MAPS > 1
    if (map == 1) return texture(u_tdepth1, uv).r;
#endif
#if DM_SHADOW_MAPS > 2
    if (map == 2) return texture(u_tdepth2, uv).r;
#endif
#if DM_SHADOW_MAPS > 3
    if (map == 3) return texture(u_tdepth3, uv).r;
#endif
    return texture(u_tdepth0, uv).r;
}

// Window depth in [0, 1] to distance from the light in mesh units.
float dm_light_distance(int i, float d)
{
    vec4 nf = u_light_depth[i];
    if (nf.z > 0.5) return nf.x + d * (nf.y - nf.x);
    float z = d * 2.0 - 1.0;
    return 2.0 * nf.x * nf.y / max(nf.y + nf.x - z * (nf.y - nf.x), 1e-20);
}

// Transmitted light of every light with a shadow map, summed (coloured by the lights): a loop
// over the DM_SHADOW_MAPS maps, not over the lights, so lights without a map cost nothing.
vec3 dm_translucency(vec3 P, vec3 Ng)
{
    vec3 sum = vec3(0.0);
    for (int j = 0; j < DM_SHADOW_MAPS; ++j) {
        int i = DM_SHADOW_LIGHT(j);
        vec3 L = dm_light_dir(i, P);
        float back = max(-dot(Ng, L), 0.0); // the geometric normal: the normal map's relief is the front's
        vec4 c = u_light_matrix[i] * vec4(P - Ng * u_shadow_normal_offset, 1.0); // shrunk inward
        vec3 p = c.xyz / c.w * 0.5 + 0.5;
        // skipped by a condition on the sum, not `continue` (llvmpipe does not unroll a loop that
        // continues: irradiance.glsl); the lookups outside the map are clamped and unused
        bool lit = back > 0.0 && !(p.x < 0.0 || p.x > 1.0 || p.y < 0.0 || p.y > 1.0 || p.z > 1.0 || p.z < 0.0);
        float first = dm_light_distance(i, dm_tdepth(j, p.xy));
        float here = dm_light_distance(i, p.z);
        float d = max(here - first, 0.0) * u_mm_per_unit;
        vec3 t = vec3(0.0);
        for (int k = 0; k < DM_TRANS_GAUSSIANS; ++k) t += u_trans_weight[k] * exp2(d * d * u_trans_var[k]);
        if (lit) sum += u_light_color[i] * (back * t);
    }
    return u_translucency * sum;
}
#endif
