#!/usr/bin/env bash
# make reference: the head's texture-space ground truth, split into tiles that GNU
# parallel runs one per core (each single-threaded), then merged into the file a one-shot
# run writes. The same command lines run as a Slurm array job (README, "dermis-reference").
# BUILD comes from the Makefile; REF_SIZE (1024), REF_TILES (16), REF_SCENE override.
set -euo pipefail
BUILD=${BUILD:-build/release}
# Scenes look up lps/..., env/... in the asset folder (make ASSETS=DIR; dm_scene.h).
export DERMIS_ASSETS=${ASSETS:-../shared/assets}
size=${REF_SIZE:-1024}
tiles=${REF_TILES:-16}
scene=${REF_SCENE:-assets/scenes/lps-sss.json}
out=build/reference
mkdir -p "$out/tiles"
rm -f "$out"/tiles/t*.exr # tiles of an earlier run would be merged too
pack="$out/$(basename "$scene" .json).dpk"
ref="$BUILD/bin/dermis-reference"
command -v parallel >/dev/null || { echo "error: GNU parallel is missing (scripts/deps.sh installs it)" >&2; exit 2; }
echo "== packing $scene"
"$BUILD/bin/dermis-pack" "$scene" -o "$pack" --quiet
echo "== $tiles tiles of the ${size}x${size} reference on $(nproc) cores (GNU parallel)"
start=$(date +%s)
parallel --will-cite --halt now,fail=1 -j "$(nproc)" \
  "$ref" "$pack" --texture-space "$size" --tile {}/"$tiles" --threads 1 --quiet -o "$out/tiles/t{}.exr" \
  ::: $(seq "$tiles")
"$ref" --merge "$out"/tiles/t*.exr -o "$out/reference-$size.exr"
echo "reference: $out/reference-$size.exr ($(( $(date +%s) - start )) s)"
echo "compare:   $BUILD/bin/dermis-render $pack --reference $out/reference-$size.exr -o $out/compare-$size.png"
