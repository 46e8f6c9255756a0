#!/usr/bin/env bash
# AddressSanitizer + UBSan build (clang, -O1 -g; sanitizer_build.sh) of the engine, emlt and
# the unit and end-to-end tests in build-asan/, then those tests (the statistical suite, the benchmark,
# the scripts and the conformance renders are left out). Any sanitizer report fails the
# run, also one from an emlt process an end-to-end test expected to fail: reports are
# written to build-asan/sanitizer-reports/ and checked after the tests.
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/sanitizer_build.sh
build=$sanitizer_build
configure_sanitizer_build
cmake --build "$build" -j "$(nproc)" --target emlt emlt_unit_tests emlt_e2e_tests

reports=$PWD/$build/sanitizer-reports
rm -rf "$reports" && mkdir -p "$reports"
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:log_path=$reports/asan"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:log_path=$reports/ubsan"
status=0
ctest --test-dir "$build" -L '^(unit|e2e)$' --output-on-failure -j "$(nproc)" || status=1

if compgen -G "$reports/*" >/dev/null; then
  echo "check_sanitizers: sanitizer reports:" >&2
  for f in "$reports"/*; do echo "== $f" >&2; cat "$f" >&2; done
  status=1
fi
[ $status -eq 0 ] && echo "check_sanitizers: unit and e2e tests clean under ASan + UBSan"
exit $status
