#!/usr/bin/env bash
# Bounded fuzz run for `make test`: builds the libFuzzer targets named as arguments and
# runs each for FUZZ_SECONDS (default 5) on a scratch copy of its seed corpus
# (fuzz/corpus/<target without "fuzz_">/). Skips with a visible notice when clang or
# libFuzzer is missing. Exit 0 when every target ran clean (or was skipped).
set -u
secs=${FUZZ_SECONDS:-5}
make_cmd=${MAKE:-make}
probe=$(mktemp -d)
trap 'rm -rf "$probe"' EXIT
printf 'int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n){(void)d;(void)n;return 0;}\n' >"$probe/p.c"
if ! command -v "${FUZZ_CC:-clang}" >/dev/null 2>&1 ||
   ! "${FUZZ_CC:-clang}" -fsanitize=fuzzer,address "$probe/p.c" -o "$probe/p" >/dev/null 2>&1; then
  echo "== fuzz: SKIPPED: ${FUZZ_CC:-clang} with libFuzzer not found (install clang libfuzzer-14-dev)" >&2
  exit 0
fi
targets=()
for t in "$@"; do targets+=("build/fuzz/$t"); done
[ ${#targets[@]} -eq 0 ] && exit 0
if ! $make_cmd --no-print-directory -j"${NPROC:-2}" "${targets[@]}" >&2; then
  echo "error: fuzz: the targets did not build" >&2
  exit 1
fi
rc=0
for t in "$@"; do
  seeds="fuzz/corpus/${t#fuzz_}"
  work="build/fuzz/corpus-${t#fuzz_}"
  rm -rf "$work" && mkdir -p "$work"
  [ -d "$seeds" ] && cp "$seeds"/* "$work"/ 2>/dev/null
  log="build/fuzz/$t.log"
  echo "== fuzz: $t for ${secs}s" >&2
  if (cd build/fuzz && ./"$t" -max_total_time="$secs" -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
        "corpus-${t#fuzz_}" >"$t.log" 2>&1); then
    echo "   $t: $(grep -E 'stat::number_of_executed_units' "$log" | awk '{print $2}') runs, no crash" >&2
  else
    echo "error: fuzz: $t found a crash; see $log" >&2
    tail -n 30 "$log" >&2
    rc=1
  fi
done
exit $rc
