#!/usr/bin/env bash
# scripts/shader-costs.sh [PACK] — where the renderer's time goes on this machine: renders
# PACK (default build/demo/lps.dpk, made by `make demo`) with copies of shaders/ that each
# leave one term out (--shader-dir), and with the speed settings, printing the per-pass
# process CPU ms (dermis-render --cpu-timings: every llvmpipe thread summed, steady when
# other work shares the cores). Medians of FRAMES frames (default 5). Used for
# docs/render-quality.md; the pictures of the variants are wrong on purpose.
set -euo pipefail
BUILD=${BUILD:-build/release}
pack=${1:-build/demo/lps.dpk}
frames=${FRAMES:-5}
[ -f "$pack" ] || { echo "error: $pack not found (run make demo first, or give a pack)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT INT TERM

# variant NAME FILE 'TEXT' 'REPLACEMENT': shaders/ with TEXT replaced in FILE (must occur)
variant() {
  mkdir -p "$work/$1" && cp shaders/*.glsl "$work/$1/"
  python3 - "$work/$1/$2" "$3" "$4" <<'PY'
import sys
path, a, b = sys.argv[1:4]
s = open(path).read()
if a not in s:
    sys.exit(f"shader-costs: '{a}' not in {path}: the shaders changed, update the script")
open(path, "w").write(s.replace(a, b))
PY
}
mkdir -p "$work/base" && cp shaders/*.glsl "$work/base/"
variant irr-no-shadow irradiance.glsl 'float k = ndl * dm_shadow(i, v_pos, Ng);' 'float k = ndl;'
variant irr-no-energy irradiance.glsl 'k *= max(1.0 - rho_s * texture(u_rho_dt, vec2(ndl, m)).r, 0.0);' ''
variant irr-no-sh irradiance.glsl 'e += u_env_intensity * dm_sh_irradiance(u_sh, dm_env_rotate(N, u_env_rotation)) / DM_PI;' ''
variant final-no-levels final.glsl 'diffuse = dm_diffusion(v_uv) * pow(albedo, vec3(1.0 - u_mix));' 'diffuse = vec3(0.0);'
variant final-no-light-specular final.glsl 'specular += u_light_color[i] * (dm_shadow(i, v_pos, Ng) * dm_ks_specular(u_beckmann, N, L, V, m, rho_s));' ''
variant final-no-env-specular final.glsl 'specular += u_env_intensity * rho_s * split * env_specular(R, m);' ''
variant blur-1-tap blur.glsl 'for (int i = 0; i < DM_TAPS; ++i)' 'for (int i = DM_TAPS / 2; i <= DM_TAPS / 2; ++i)'
variant blur-3-taps blur.glsl 'for (int i = 0; i < DM_TAPS; ++i)' 'for (int i = DM_TAPS / 2 - 1; i <= DM_TAPS / 2 + 1; ++i)'
variant blur-no-stretch-fetch blur.glsl 'vec2 s = texture(u_stretch, v_uv).rg;' 'vec2 s = vec2(0.002);'

run() { # NAME ARGS...: one line of per-pass medians
  local name=$1; shift
  "$BUILD/bin/dermis-render" "$pack" -o "$work/out.exr" --frames "$frames" --cpu-timings --quiet "$@" |
    awk -v n="$name" '/^[a-z_0-9]+ +[0-9.]+$/ { v[$1] = $2; if ($1 ~ /^blur_/) b += $2; if ($1 ~ /^glow/) g += $2 }
      END { printf "| %s | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | **%.0f** |\n", n, v["shadow0"], v["irradiance"], b,
            v["gbuffer"] + v["final"], g + v["background"] + v["tonemap"], v["tonemap"], v["frame"] }'
}
echo "Per-pass process CPU ms, median of $frames frames, $pack; $(nproc) cores; load $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| variant | shadow | irradiance | blur (all) | G-buffer + final | background+glow+tonemap | tonemap | frame |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
run base --shader-dir "$work/base"
for v in irr-no-shadow irr-no-energy irr-no-sh final-no-levels final-no-light-specular \
         final-no-env-specular; do
  run "$v" --shader-dir "$work/$v"
done
# blur.glsl runs only with the blur in GL (on llvmpipe the default runs it on the CPU)
run "--blur-on gl" --blur-on gl
for v in blur-1-tap blur-3-taps blur-no-stretch-fetch; do
  run "$v (in GL)" --shader-dir "$work/$v" --blur-on gl
done
run "--pcf-taps 1" --pcf-taps 1
run "--pcf-taps 9" --pcf-taps 9
run "--half-float" --half-float
run "--blur-auto" --blur-auto
run "--blur-reduce-from 3" --blur-reduce-from 3
