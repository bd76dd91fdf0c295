#!/usr/bin/env bash
# make gallery: the bundled head at six skin parameter sets (Fitzpatrick 1-6, our mapping onto
# Jacques' melanosome bands: dermis-fit-profile --list-presets), each packed from
# assets/scenes/lps-skin.json with that preset as the profile and, by "albedo_from": "skin", as
# the colour, rendered headless and set side by side into docs/gallery.png; and the presets'
# profiles and spectra, written by dermis-fit-profile --radial / --spectrum, plotted by gnuplot
# (scripts/skin-plots.gp) into docs/skin-profiles.png and docs/skin-spectra.png.
# Run by `make gallery` after the tools are built; BUILD and ASSETS come from the Makefile.
set -euo pipefail
BUILD=${BUILD:-build/release}
ASSETS=${ASSETS:-../shared/assets}
out=build/gallery
presets=(fitzpatrick-1 fitzpatrick-2 fitzpatrick-3 fitzpatrick-4 fitzpatrick-5 fitzpatrick-6)
font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
if [ ! -f "$ASSETS/lps/LeePerrySmith.obj" ]; then
  echo "error: the head scan is not at $ASSETS/lps/LeePerrySmith.obj: give the asset folder with make gallery ASSETS=DIR" >&2
  exit 2
fi
for tool in oiiotool gnuplot; do
  command -v "$tool" >/dev/null || { echo "error: $tool is missing: make deps installs it" >&2; exit 2; }
done
export DERMIS_ASSETS=$ASSETS
mkdir -p "$out"
base=assets/scenes/lps-skin.json
grep -q '"preset": "fitzpatrick-3"' "$base" || { echo "error: $base no longer names fitzpatrick-3" >&2; exit 3; }

tiles=()
: > "$out/colours.txt"
for p in "${presets[@]}"; do
  sed "s/\"preset\": \"fitzpatrick-3\"/\"preset\": \"$p\"/" "$base" > "$out/$p.json"
  # -v: the packer's line on the colour it baked (the model's total, the result's mean over the skin)
  "$BUILD/bin/dermis-pack" "$out/$p.json" -o "$out/$p.dpk" -v 2>&1 >/dev/null | grep '^albedo from the skin' |
    tee -a "$out/colours.txt"
  "$BUILD/bin/dermis-render" "$out/$p.dpk" -o "$out/$p.png" --quiet
  if [ -f "$font" ]; then
    oiiotool "$out/$p.png" --text:x=12:y=28:size=20:color=1,1,1:font="$font" "$p" -o "$out/$p-label.png"
    tiles+=("$out/$p-label.png")
  else
    tiles+=("$out/$p.png")
  fi
  "$BUILD/bin/dermis-fit-profile" --skin-preset "$p" --radial "$out/$p.radial.tsv" --spectrum "$out/$p.spectrum.tsv" --quiet
done
oiiotool "${tiles[@]}" --mosaic 6x1 -o docs/gallery.png
gnuplot -e "dir='$out'" scripts/skin-plots.gp
echo "pictures: docs/gallery.png docs/skin-profiles.png docs/skin-spectra.png (packs, renders, tables: $out/)"
