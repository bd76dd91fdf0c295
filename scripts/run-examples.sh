#!/usr/bin/env bash
# Runs every shell example of README.md and docs/*.md (the ```sh blocks), in order, as
# printed, in one shell, in a fresh copy of the checkout (tracked and untracked files that
# git does not ignore) with the asset folder beside it as ../shared/assets, the way a new
# user would after cloning. Run by tests/unit/test_examples.c (make test); by hand:
#   DERMIS_BIN=$PWD/build/release/bin DERMIS_ASSETS=../shared/assets bash scripts/run-examples.sh
# Exit 0 when every command succeeded; else the failing command and where it is printed.
#
# What is not run as printed, and why (each rule is the only one of its kind):
#   - a block right after a line "<!-- examples: not run (REASON) -->";
#   - a dermis-view command (interactive: it needs a display and a person; tests/view drives
#     it under Xvfb with --script);
#   - `make test` (this script is part of it); `make demo` and `make gallery` run as
#     scripts/demo.sh and scripts/gallery.sh, which is what they do once the tools are built;
#   - `--texture-space 256` runs at 64 and `--atlas 256` at 128 (the ground truth at 256²
#     takes ~1 min on 2 cores, the frame's atlas ~20 s; the same code paths, fewer texels).
# In a block whose lines start with "$ " (a command followed by its output), only those
# lines run.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${DERMIS_BIN:?give DERMIS_BIN, the tools folder (absolute)}
assets=${DERMIS_ASSETS:?give DERMIS_ASSETS, the asset folder}
assets=$(cd "$assets" && pwd)
work=$(mktemp -d "${DERMIS_TEST_TMP:-/tmp}/dermis-examples-XXXXXX")
mkdir -p "$work/checkout/build" "$work/shared"
ln -s "$assets" "$work/shared/assets"
(cd "$root" && git ls-files -z -co --exclude-standard | tar --null --ignore-failed-read -T - -cf - 2>/dev/null) |
  tar -C "$work/checkout" -xf -
ln -s "$(cd "$bin/.." && pwd)" "$work/checkout/build/release"

# The examples as one script, each command preceded by where it is printed.
script="$work/examples.sh"
{
  echo 'set -eo pipefail'
  echo 'trap '"'"'echo "error: the example at $where failed (exit $?): $cmd" >&2'"'"' ERR'
  for f in README.md $(cd "$root" && ls docs/*.md); do
    awk -v F="$f" -v Q="'" '
      /^<!-- examples: not run/ { skip = 1; next }
      /^```sh[[:space:]]*$/ { inblock = 1; n = 0; next }
      inblock && /^```/ {
        inblock = 0
        if (!skip) {
          prompt = 0
          for (k = 1; k <= n; ++k) if (line[k] ~ /^\$ /) prompt = 1
          for (k = 1; k <= n; ++k) {
            c = line[k]
            if (prompt) { if (c !~ /^\$ /) continue; c = substr(c, 3) }
            if (c ~ /^[[:space:]]*$/ || c ~ /^[^#]*dermis-view /) continue
            if (c ~ /^make test/) continue
            sub(/^make demo/, "BUILD=build/release ASSETS=../shared/assets bash scripts/demo.sh", c)
            sub(/^make gallery/, "BUILD=build/release ASSETS=../shared/assets bash scripts/gallery.sh", c)
            gsub(/--texture-space 256/, "--texture-space 64", c)
            gsub(/--atlas 256/, "--atlas 128", c)
            shown = c; gsub(Q, "", shown)
            printf "where=%s%s:%d%s cmd=%s%s%s; echo \"+ $cmd   ($where)\" >&2; s=$SECONDS\n", Q, F, where[k], Q, Q, shown, Q
            printf "%s\n", c
            printf "echo \"  ok ($((SECONDS - s)) s)\" >&2\n"
          }
        }
        skip = 0; next
      }
      inblock { line[++n] = $0; where[n] = NR; next }
      /[^[:space:]]/ { skip = 0 }
    ' "$root/$f"
  done
} >"$script"

count=$(grep -c '^where=' "$script")
echo "running $count example commands from README.md and docs/*.md in $work/checkout" >&2
start=$SECONDS
if ! (cd "$work/checkout" && bash "$script"); then
  echo "note: the examples' files are in $work/checkout" >&2
  exit 1
fi
echo "all $count example commands ran ($((SECONDS - start)) s)" >&2
rm -rf "$work"
