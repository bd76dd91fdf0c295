#!/usr/bin/env bash
# Runs each benchmark binary given; each writes its Markdown table under bench/results/.
set -eu
mkdir -p bench/results
for b in "$@"; do
  echo "== $(basename "$b")" >&2
  "$b" bench/results
done
