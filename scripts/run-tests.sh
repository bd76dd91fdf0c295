#!/usr/bin/env bash
# Runs each Criterion test binary given, then prints one synthesis line over all of them.
# Exit 0 only when every binary ran and every test passed.
set -u
# Scenes look up lps/..., env/... in the asset folder (make ASSETS=DIR; dm_scene.h).
export DERMIS_ASSETS=${ASSETS:-../shared/assets}
# Sanitizer builds: leaks inside third-party libraries are suppressed by module name
# (scripts/lsan-third-party.supp); release builds ignore these variables.
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/scripts/lsan-third-party.supp:print_suppressions=0}
tested=0 passing=0 failing=0 crashing=0 broken=0
jobs=${DERMIS_TEST_JOBS:-2}
# One scratch root per run for the tests' files (packs of tens of MiB among them):
# removed when everything passed, kept and named when something failed.
scratch=$(mktemp -d /tmp/dermis-run-XXXXXX)
export DERMIS_TEST_TMP=$scratch
for t in "$@"; do
  name=${t#"$BUILD"/tests/}
  echo "== $name" >&2
  run=()
  # tests/view/ drive the GLFW viewer: they need a display, given by xvfb-run
  if [[ $name == view/* ]]; then
    if ! command -v xvfb-run >/dev/null; then
      echo "notice: $name skipped: xvfb-run is missing (apt-get install xvfb xauth)" >&2
      continue
    fi
    run=(xvfb-run -a)
    # The viewer's GL driver (Mesa's DRI module, loaded by GLX) is unloaded at exit, so the
    # allocations it keeps come from an unknown module that no suppression can name:
    # leak checking is off for the viewer (TOOLCHAIN.md), on for everything else; the
    # renderer it shares is leak-checked in the OSMesa tools and tests.
    run=(env "ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" xvfb-run -a)
  fi
  log=$(mktemp)
  t0=$SECONDS
  "${run[@]}" "$t" -j"$jobs" 2>&1 | tee "$log" | grep -vE '^\[====\] Synthesis' >&2
  rc=${PIPESTATUS[0]}
  line=$(grep -E '^\[====\] Synthesis: Tested:' "$log" | tail -n 1)
  rm -f "$log"
  if [ -z "$line" ]; then
    echo "error: $name printed no synthesis line (exit $rc)" >&2
    broken=$((broken + 1)); continue
  fi
  read -r t_ p_ f_ c_ <<<"$(echo "$line" | sed -E 's/.*Tested: ([0-9]+) \| Passing: ([0-9]+) \| Failing: ([0-9]+) \| Crashing: ([0-9]+).*/\1 \2 \3 \4/')"
  tested=$((tested + t_)); passing=$((passing + p_)); failing=$((failing + f_)); crashing=$((crashing + c_))
  echo "   $name: $p_/$t_ passed ($((SECONDS - t0)) s)" >&2
  if [ "$rc" -ne 0 ] && [ "$f_" -eq 0 ] && [ "$c_" -eq 0 ]; then broken=$((broken + 1)); fi
done
# The bounded fuzz runs (scripts/run-fuzz.sh) ran before; a failure there counts here,
# so this synthesis stays the last line of `make test`.
if [ "${FUZZ_FAILED:-0}" -ne 0 ]; then
  echo "error: a fuzz target failed (see above)" >&2
  broken=$((broken + 1))
fi
if [ "$failing" -eq 0 ] && [ "$crashing" -eq 0 ] && [ "$broken" -eq 0 ]; then
  rm -rf "$scratch"
else
  echo "note: the failing tests' files are in $scratch" >&2
fi
echo "[====] Synthesis: Tested: $tested | Passing: $passing | Failing: $failing | Crashing: $crashing"
echo "$passing passed, $((failing + crashing + broken)) failed"
[ "$failing" -eq 0 ] && [ "$crashing" -eq 0 ] && [ "$broken" -eq 0 ] && [ "$tested" -gt 0 ]
