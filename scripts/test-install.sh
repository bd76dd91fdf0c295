#!/usr/bin/env bash
# test-install.sh MODE — checks `make install` into a staged DESTDIR, as a packager and an
# engine programmer would use it. Run by tests/unit/test_install.c (make test), one MODE per
# test; by hand: DERMIS_ASSETS=../shared/assets bash scripts/test-install.sh tree
#
#   tree        the installed file list; then, with the checkout hidden (a private mount
#               namespace lays an empty folder over it), every installed tool's --help and
#               --version, every man page rendered by man(1), and the demo packed, checked and
#               rendered by the installed tools from the installed scene
#   man         every option each tool's --help prints appears in its rendered man page; the
#               format pages (section 5) render and state their version policy
#   completion  every option each tool's --help prints completes from its installed bash
#               completion, and option values complete as the help lists them
#   pkgconfig   the .pc files resolve inside the staged tree; the runtime's (dermis) link line
#               names none of OpenEXR, OpenImageIO, OpenMesh, Embree; every installed header
#               compiles on its own with only the .pc's flags
#   examples    the installed examples/embed build with the staged .pc files alone and, with the
#               checkout hidden, draw the demo pack (draw_pack: own GL; render_into_fbo: the
#               renderer into the caller's framebuffer, equal to dermis-render's picture)
#   uninstall   make uninstall removes every file make install put there
#
# Environment: DERMIS_CONFIG (release, debug or sanitize: the build to install; default
# release), DERMIS_ASSETS (the head scan's folder), DERMIS_TEST_TMP (scratch root).
set -euo pipefail
mode=${1:?usage: test-install.sh tree|man|completion|pkgconfig|examples|uninstall}
root=$(cd "$(dirname "$0")/.." && pwd)
config=${DERMIS_CONFIG:-release}
assets=$(cd "${DERMIS_ASSETS:?give DERMIS_ASSETS, the asset folder}" && pwd)
work=$(mktemp -d "${DERMIS_TEST_TMP:-/tmp}/dermis-install-$mode-XXXXXX")
dest=$work/dest
prefix=/usr
fail() { echo "test-install $mode: FAIL: $*" >&2; exit 1; }
say() { echo "== $*"; }

# The test runs inside `make test`: the outer make's jobserver must not leak into ours.
unset MAKEFLAGS MFLAGS MAKELEVEL
say "make install DESTDIR=$dest PREFIX=$prefix config=$config"
# Criterion runs two of these at once: one make at a time in the build folder, so what is out
# of date (a script newer than the man pages it makes, say) is remade once, not raced.
mkdir -p "$root/build/$config"
flock "$root/build/$config/.install-lock" make -C "$root" --no-print-directory install \
  DESTDIR="$dest" PREFIX="$prefix" config="$config" >"$work/install.log" 2>&1 ||
  { cat "$work/install.log" >&2; fail "make install failed"; }
bin=$dest$prefix/bin
# the staged .pc files are relocatable (the Makefile): PKG_CONFIG_PATH alone finds them
export PKG_CONFIG_PATH=$dest$prefix/lib/pkgconfig
tools=$(cd "$root/tools" && ls *.c | sed 's/\.c$//')
[ -x "$root/build/$config/bin/dermis-view" ] || tools=$(echo "$tools" | grep -v '^dermis-view$')
# what this script needs once the checkout is hidden: help-options.sh, and the sanitizer
# build's leak suppressions (scripts/run-tests.sh names them by their path in the checkout)
cp "$root/scripts/help-options.sh" "$work/"
if [[ ${LSAN_OPTIONS:-} =~ (^|:)suppressions=([^:]*) ]]; then
  supp=${BASH_REMATCH[2]}
  cp "$supp" "$work/lsan.supp" && export LSAN_OPTIONS=${LSAN_OPTIONS/"suppressions=$supp"/"suppressions=$work/lsan.supp"}
fi

# Runs a script with the checkout hidden: root (or a user namespace) mounts an empty tmpfs
# over it, so nothing in it — sources, build folder, shaders — can be reached. Where no
# namespace can be made (an unprivileged user without user namespaces) it runs with the
# checkout visible, after checking that no installed binary names the build folder.
hidden() {
  local script=$1
  if unshare -m --propagation private true 2>/dev/null; then
    unshare -m --propagation private bash -c 'mount -t tmpfs none "$0" && cd / && bash "$1"' "$root" "$script"
  elif unshare -rm --propagation private true 2>/dev/null; then
    unshare -rm --propagation private bash -c 'mount -t tmpfs none "$0" && cd / && bash "$1"' "$root" "$script"
  else
    echo "note: no mount namespace here: the checkout stays visible; checking the binaries instead" >&2
    if grep -l "$root/build" "$bin"/* >/dev/null 2>&1; then fail "an installed binary names $root/build"; fi
    (cd / && bash "$script")
  fi
}

case $mode in
tree)
  say "installed files"
  (cd "$dest" && find . -type f | sort) | tee "$work/files.txt"
  for t in $tools; do
    for f in "usr/bin/$t" "usr/share/man/man1/$t.1" "usr/share/bash-completion/completions/$t"; do
      grep -qx "./$f" "$work/files.txt" || fail "$f is not installed"
    done
  done
  for f in usr/lib/libdermis_core.a usr/lib/libdermis_render.a usr/lib/libdermis_host_osmesa.a \
           usr/lib/libdermis_bake.a usr/lib/pkgconfig/dermis.pc usr/lib/pkgconfig/dermis-osmesa.pc \
           usr/lib/pkgconfig/dermis-bake.pc usr/share/man/man5/dermis-scene.5 usr/share/man/man5/dermis-dpk.5 \
           usr/include/dermis/pack/dm_pack.h usr/include/dermis/render/dm_render.h \
           usr/include/dermis/host/dm_osmesa.h usr/share/dermis/scenes/lps.json \
           usr/share/doc/dermis/examples/embed/Makefile; do
    grep -qx "./$f" "$work/files.txt" || fail "$f is not installed"
  done
  if grep -E '_impl\.h$|_internal\.h$' "$work/files.txt"; then fail "a private header is installed"; fi
  if grep -vE '^\./usr/' "$work/files.txt"; then fail "a file was installed outside PREFIX"; fi
  cat >"$work/run.sh" <<EOF
set -euo pipefail
export PATH=$bin:/usr/bin:/bin DERMIS_ASSETS=$assets MANWIDTH=100
[ -e "$root/Makefile" ] && { echo "the checkout is not hidden" >&2; exit 1; }
for t in $(echo $tools); do
  out=\$(\$t --help) || { echo "\$t --help failed" >&2; exit 1; }
  case \$out in *Usage:*) ;; *) echo "\$t --help prints no Usage: line" >&2; exit 1 ;; esac
  [ "\$(\$t --version)" = "\$t $(sed -n 's/^#define DM_VERSION "\(.*\)"/\1/p' "$root/lib/core/dm_version.h")" ] ||
    { echo "\$t --version: '\$(\$t --version)'" >&2; exit 1; }
  echo "\$t: --help and --version ok"
done
for p in $dest$prefix/share/man/man*/*; do
  text=\$(man -l "\$p" 2>"$work/man.err") || { cat "$work/man.err" >&2; exit 1; }
  [ -s "$work/man.err" ] && { echo "man -l \$p warns:" >&2; cat "$work/man.err" >&2; exit 1; }
  case \$text in *NAME*DESCRIPTION*) ;; *) echo "\$p has no NAME and DESCRIPTION" >&2; exit 1 ;; esac
  echo "man -l \$(basename \$p): \$(echo "\$text" | wc -l) lines"
done
cd "$work"
dermis-pack $dest$prefix/share/dermis/scenes/lps.json -o lps.dpk --quiet
dermis-check lps.dpk
dermis-render lps.dpk -o lps.png --quiet
[ -s lps.png ] || { echo "no picture" >&2; exit 1; }
echo "demo packed, checked and rendered by the installed tools: \$(stat -c %s lps.png) bytes"
EOF
  hidden "$work/run.sh" || fail "the installed tree does not run on its own"
  ;;
man)
  for t in $tools; do
    page=$dest$prefix/share/man/man1/$t.1
    MANWIDTH=200 man -l "$page" 2>/dev/null | col -b >"$work/$t.txt"
    n=0
    while IFS=$'\t' read -r opt _; do
      grep -qF -- "$opt" "$work/$t.txt" || fail "$t: option $opt of --help is not in $t.1"
      n=$((n + 1))
    done < <(bash "$root/scripts/help-options.sh" "$root/build/$config/bin/$t")
    [ "$n" -ge 3 ] || fail "$t: only $n options found in --help"
    echo "$t.1: all $n options of --help"
  done
  for p in dermis-scene dermis-dpk; do
    text=$(MANWIDTH=100 man -l "$dest$prefix/share/man/man5/$p.5" 2>/dev/null | col -b)
    case $text in *"VERSION POLICY"*) ;; *) fail "$p.5 has no VERSION POLICY section" ;; esac
    echo "$p.5: $(echo "$text" | wc -l) lines, with its version policy"
  done
  ;;
completion)
  for t in $tools; do
    comp=$dest$prefix/share/bash-completion/completions/$t
    fn=$(sed -n 's/^complete -F \([^ ]*\) .*/\1/p' "$comp")
    [ -n "$fn" ] || fail "$comp defines no completion"
    n=0
    while IFS=$'\t' read -r opt val; do
      got=$(bash -c 'source "$1"; COMP_WORDS=("$2" "$3"); COMP_CWORD=1; "$4"; printf "%s\n" "${COMPREPLY[@]}"' \
        _ "$comp" "$t" "$opt" "$fn" 2>/dev/null)
      grep -qx -- "$opt" <<<"$got" || fail "$t: '$t $opt<TAB>' does not complete to $opt (got: $got)"
      if [[ $val =~ ^[a-z0-9-]+(\|[a-z0-9-]+)+$ ]]; then
        want=$(tr '|' '\n' <<<"$val")
        got=$(bash -c 'source "$1"; COMP_WORDS=("$2" "$3" ""); COMP_CWORD=2; "$4"; printf "%s\n" "${COMPREPLY[@]}"' \
          _ "$comp" "$t" "$opt" "$fn" 2>/dev/null)
        [ "$got" = "$want" ] || fail "$t $opt: values complete to '$got', --help lists '$val'"
      fi
      n=$((n + 1))
    done < <(bash "$root/scripts/help-options.sh" "$root/build/$config/bin/$t")
    got=$(bash -c 'source "$1"; COMP_WORDS=("$2" --vers); COMP_CWORD=1; "$3"; printf "%s\n" "${COMPREPLY[@]}"' \
      _ "$comp" "$t" "$fn" 2>/dev/null)
    [ "$got" = --version ] || fail "$t: --vers completes to '$got'"
    echo "$t: $n options complete"
  done
  ;;
pkgconfig)
  pkg-config --exists --print-errors dermis dermis-osmesa dermis-bake || fail "pkg-config cannot resolve the .pc files"
  [ "$(pkg-config --modversion dermis)" = "$(sed -n 's/^#define DM_VERSION "\(.*\)"/\1/p' "$root/lib/core/dm_version.h")" ] ||
    fail "dermis.pc's version"
  for m in dermis dermis-osmesa; do
    flags="$(pkg-config --static --cflags --libs $m)"
    echo "$m: $flags"
    if grep -qiE 'openexr|openimageio|openmesh|embree|tinygltf' <<<"$flags"; then fail "$m names an offline library"; fi
    inc=$(pkg-config --cflags-only-I $m | tr ' ' '\n' | sed -n 's/^-I//p' | head -n 1)
    [ "$(realpath -m "$inc")" = "$dest$prefix/include/dermis" ] || fail "$m's Cflags name $inc, not the staged headers"
  done
  echo "dermis-bake: $(pkg-config --static --libs dermis-bake)"
  n=0
  for h in $(cd "$dest$prefix/include/dermis" && find . -name '*.h' | sort); do
    h=${h#./}
    m=dermis; case $h in bake/*) m=dermis-bake ;; host/*) m=dermis-osmesa ;; esac
    printf '#include "%s"\ntypedef int dm_header_check;\n' "$h" | cc -std=c11 -Wall -Wextra -Wpedantic -Werror -fsyntax-only -x c - \
      $(pkg-config --cflags $m) 2>"$work/h.err" || { cat "$work/h.err" >&2; fail "$h does not compile on its own ($m)"; }
    n=$((n + 1))
  done
  echo "$n installed headers compile on their own with -std=c11 -Wall -Wextra -Wpedantic -Werror"
  ;;
examples)
  cp -r "$dest$prefix/share/doc/dermis/examples/embed" "$work/embed"
  cat >"$work/run.sh" <<EOF
set -euo pipefail
export PATH=$bin:/usr/bin:/bin DERMIS_ASSETS=$assets
[ -e "$root/Makefile" ] && { echo "the checkout is not hidden" >&2; exit 1; }
cd "$work"
make -C embed --no-print-directory
wc -l embed/*.c
dermis-pack $dest$prefix/share/dermis/scenes/lps.json -o lps.dpk --quiet
embed/draw_pack lps.dpk draw.png 640 360
embed/render_into_fbo lps.dpk fbo.png 640 360
dermis-render lps.dpk -o render.png --size 640x360 --quiet
idiff fbo.png render.png
oiiotool draw.png --printstats >stats.txt
grep -E 'Stats (Min|Max)' stats.txt
EOF
  hidden "$work/run.sh" || fail "the embedding examples do not build or run against the staged install"
  # draw_pack drew something: its picture is not one flat colour
  min=$(sed -n 's/.*Stats Min: *\([0-9.]*\).*/\1/p' "$work/stats.txt" | head -n 1)
  max=$(sed -n 's/.*Stats Max: *\([0-9.]*\).*/\1/p' "$work/stats.txt" | head -n 1)
  [ -n "$min" ] && [ "$min" != "$max" ] || fail "draw_pack's picture is one flat colour ($min..$max)"
  ;;
uninstall)
  make -C "$root" --no-print-directory uninstall \
    DESTDIR="$dest" PREFIX="$prefix" config="$config" >"$work/uninstall.log" 2>&1 ||
    { cat "$work/uninstall.log" >&2; fail "make uninstall failed"; }
  left=$(cd "$dest" && find . -type f -o -type l)
  [ -z "$left" ] || fail "make uninstall left: $left"
  echo "make uninstall removed every installed file"
  ;;
*) fail "unknown mode" ;;
esac
rm -rf "$work"
echo "test-install $mode: ok"
