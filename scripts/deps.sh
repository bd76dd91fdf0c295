#!/usr/bin/env bash
# Installs the Debian 12 packages dermis needs that are missing; does nothing when all
# are present. Uses sudo when not root. Set DERMIS_DEPS_OPTIONAL=0 to skip the optional
# ones (the viewer's UI library, plots, the fuzzer).
set -euo pipefail

required=(
  build-essential pkg-config
  libopenmesh-dev libopenimageio-dev openimageio-tools libopenexr-dev openexr
  libglfw3-dev libosmesa6-dev xvfb xauth libglx-mesa0 libgl1-mesa-dri
  libcriterion-dev libcjson-dev libxxhash-dev zlib1g-dev
  libembree-dev libtinygltf-dev parallel
  help2man go-md2man man-db bsdextrautils bash-completion
)
optional=(libimgui-dev gnuplot-nox clang libfuzzer-14-dev libclang-rt-14-dev)

want=("${required[@]}")
if [ "${DERMIS_DEPS_OPTIONAL:-1}" != 0 ]; then want+=("${optional[@]}"); fi

missing=()
for p in "${want[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "deps: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
