#!/usr/bin/env bash
# make demo: bakes what the bundled head needs and renders it (the renderer and packer
# join this script as they land). Run by `make demo` after the tools are built.
set -euo pipefail
BUILD=${BUILD:-build/release}
ASSETS=${ASSETS:-../shared/assets}
out=build/demo
mkdir -p "$out"
echo "== baking the specular lookup tables"
"$BUILD/bin/dermis-bake-lut" -o "$out" --report
echo
echo "demo outputs are in $out/"
