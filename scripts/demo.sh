#!/usr/bin/env bash
# make demo: packs the bundled head scene (assets/scenes/lps.json: every effect) and
# renders it headless, then prints the pass timings and where the picture is.
# Run by `make demo` after the tools are built; BUILD and ASSETS come from the Makefile.
set -euo pipefail
BUILD=${BUILD:-build/release}
ASSETS=${ASSETS:-../shared/assets}
out=build/demo
mkdir -p "$out"
scene=assets/scenes/lps.json
if [ ! -f "$ASSETS/lps/LeePerrySmith.obj" ]; then
  echo "error: the head scan is not at $ASSETS/lps/LeePerrySmith.obj: give the asset folder with make demo ASSETS=DIR" >&2
  exit 2
fi
# The bundled scenes name their files relative to the asset folder (lps/..., env/...).
export DERMIS_ASSETS=$ASSETS
echo "== packing $scene (bakes only what its effects need)"
"$BUILD/bin/dermis-pack" "$scene" -o "$out/lps.dpk"
echo
echo "== checking the pack"
"$BUILD/bin/dermis-check" "$out/lps.dpk"
echo
echo "== rendering (OSMesa, llvmpipe), 3 frames, median ms per pass"
"$BUILD/bin/dermis-render" "$out/lps.dpk" -o "$out/lps.png" --frames 3 --timings
echo
echo "picture: $out/lps.png"
echo "interactive: $BUILD/bin/dermis-view $out/lps.dpk   (needs a display)"
