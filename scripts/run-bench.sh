#!/usr/bin/env bash
# Runs each benchmark binary given; each writes its Markdown table under bench/results/.
set -eu
# Scenes look up lps/..., env/... in the asset folder (make ASSETS=DIR; dm_scene.h).
export DERMIS_ASSETS=${ASSETS:-../shared/assets}
mkdir -p bench/results
for b in "$@"; do
  echo "== $(basename "$b")" >&2
  "$b" bench/results
done
