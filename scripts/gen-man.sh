#!/usr/bin/env bash
# gen-man.sh TOOL — prints the tool's section-1 man page, made by help2man from its --help
# and --version at build time (so the page cannot drift from the tool), with the sections
# every dermis tool shares (scripts/man-common.h2m: exit status, environment, files, see
# also). The NAME line's summary is the one table below.
set -euo pipefail
tool=${1:?usage: gen-man.sh TOOL}
here=$(cd "$(dirname "$0")" && pwd)
case $(basename "$tool") in
  dermis-bake-lut)       what="bake the specular lookup tables of the skin model" ;;
  dermis-bake-stretch)   what="bake UV stretch maps and their blurred chain from a mesh" ;;
  dermis-bake-curvature) what="bake per-texel mean curvature from a mesh for pre-integrated skin" ;;
  dermis-bake-seams)     what="bake the seam map that lets texture-space diffusion blur across UV seams" ;;
  dermis-bake-thin)      what="bake the thin-part map that lets texture-space diffusion reach through thin parts and across folds" ;;
  dermis-bake-env)       what="bake an HDR environment into SH irradiance and prefiltered specular levels" ;;
  dermis-fit-profile)    what="fit a diffusion profile with a sum of Gaussians" ;;
  dermis-pack)           what="bake what a scene's effects need into one GPU-ready .dpk pack" ;;
  dermis-check)          what="validate dermis packs, lookup tables, maps, profiles and scenes" ;;
  dermis-reference)      what="the ground truth of subsurface diffusion by exact surface convolution" ;;
  dermis-render)         what="render a dermis pack headless (OSMesa)" ;;
  dermis-view)           what="show a dermis pack interactively" ;;
  *) echo "gen-man.sh: no summary for $(basename "$tool"): add it to the table" >&2; exit 1 ;;
esac
# help2man reads a second synopsis only as "  or: TOOL ..." and a synopsis only on one line:
# the tools align theirs under the first and wrap long ones, so help2man runs the tool
# through a wrapper of the same name that joins and relabels those lines (the rest of the
# help text passes through unchanged).
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
name=$(basename "$tool")
tool_abs=$(cd "$(dirname "$tool")" && pwd)/$name
cat >"$tmp/$name" <<WRAP
#!/usr/bin/env bash
if [ "\$1" = --help ]; then
  "$tool_abs" --help | awk '
    usage && /^ +$name / { print held; held = \$0; sub(/^ +/, "  or: ", held); next }
    usage && /^ +[[(-]/ { sub(/^ +/, " "); held = held \$0; next }
    NR == 1 { held = \$0; usage = 1; next }
    usage { print held; usage = 0 }
    { print }
    END { if (usage) print held }'
else
  exec "$tool_abs" "\$@"
fi
WRAP
chmod +x "$tmp/$name"
# The page's date is SOURCE_DATE_EPOCH's (the Makefile gives the last commit's), so the same
# sources make the same page.
SOURCE_DATE_EPOCH=${SOURCE_DATE_EPOCH:-$(date +%s)} help2man -N -n "$what" --section 1 --manual "dermis manual" \
  --include "$here/man-common.h2m" "$tmp/$name"
