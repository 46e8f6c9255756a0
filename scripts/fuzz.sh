#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) into build-asan/ (the sanitizer build of
# check_sanitizers.sh, sanitizer_build.sh) and runs one of them:
#   scripts/fuzz.sh TARGET SECONDS     e.g. scripts/fuzz.sh obj 600
#   scripts/fuzz.sh all SECONDS        every target in turn, two at a time (CI)
#   scripts/fuzz.sh list               the targets (tests/fuzz/fuzz_TARGET.cpp)
# Seeds and regression inputs: tests/fuzz/corpus/TARGET/ (read only); what the run adds
# goes to build-asan/corpus/TARGET/, a crash to build-asan/artifacts/TARGET/. A crash,
# sanitizer report, leak, out-of-memory or hang (10 s) exits non-zero.
set -euo pipefail
cd "$(dirname "$0")/.."

targets() { ls tests/fuzz/fuzz_*.cpp | sed 's|.*/fuzz_||; s|\.cpp$||'; }

if [ "${1:-}" = list ]; then targets; exit 0; fi
if [ $# -ne 2 ]; then
  echo "usage: scripts/fuzz.sh TARGET|all SECONDS (targets: $(targets | tr '\n' ' '))" >&2
  exit 2
fi
target=$1 seconds=$2
if [ "$target" != all ] && [ ! -f "tests/fuzz/fuzz_$target.cpp" ]; then
  echo "fuzz: no target '$target' (targets: $(targets | tr '\n' ' '))" >&2
  exit 2
fi

source scripts/sanitizer_build.sh
build=$sanitizer_build
configure_sanitizer_build
if [ "$target" = all ]; then
  cmake --build "$build" -j "$(nproc)" -- $(targets | sed 's/^/fuzz_/')
else
  cmake --build "$build" -j "$(nproc)" --target "fuzz_$target"
fi

run_one() {
  local t=$1
  mkdir -p "$build/corpus/$t" "$build/artifacts/$t"
  # `all` is what CI runs: a fixed seed, so that a run explores the same inputs each time
  # and CI does not fail at random on a finding nobody has seen; one target alone (the
  # long campaigns) draws a new seed each run.
  local seed=0
  [ "$target" = all ] && seed=1
  local dict=()
  [ -f "tests/fuzz/$t.dict" ] && dict=(-dict="tests/fuzz/$t.dict")
  # Findings are fatal; emlt::Error is a normal outcome (tests/fuzz/fuzz_input.h).
  local rc=0
  ASAN_OPTIONS=halt_on_error=1:detect_leaks=1 \
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    "$build/tests/fuzz/fuzz_$t" "$build/corpus/$t" "tests/fuzz/corpus/$t" "${dict[@]}" \
      -seed="$seed" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 -max_len=65536 \
      -print_final_stats=1 -artifact_prefix="$build/artifacts/$t/" >"$build/fuzz-$t.log" 2>&1 ||
    rc=$?
  grep -E '^(#[0-9]+[[:space:]]+DONE|stat::number_of_executed_units|stat::peak_rss_mb)' "$build/fuzz-$t.log" |
    sed "s/^/fuzz $t: /" || true
  if [ $rc -ne 0 ]; then
    echo "fuzz $t: FAILED (exit $rc), see $build/fuzz-$t.log:" >&2
    tail -n 40 "$build/fuzz-$t.log" >&2
  fi
  return $rc
}

if [ "$target" != all ]; then run_one "$target"; exit; fi
failed=0
mapfile -t all < <(targets)
for ((i = 0; i < ${#all[@]}; i += 2)); do
  pids=()
  for t in "${all[@]:i:2}"; do run_one "$t" & pids+=($!); done
  for p in "${pids[@]}"; do wait "$p" || failed=1; done
done
exit $failed
