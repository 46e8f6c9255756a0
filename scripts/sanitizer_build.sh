# Sourced by check_sanitizers.sh and fuzz.sh: one clang build in build-asan/ with
# AddressSanitizer + UBSan (every report fatal) and libFuzzer's coverage hooks, so that the
# unit and end-to-end tests under the sanitizers and the fuzz targets share one compile of
# the engine (two separate builds were about a sixth of CI's time). Line tables are all the
# sanitizers' stack traces need, and compile faster than full debug information.
sanitizer_build=build-asan

configure_sanitizer_build() {
  CC=clang-14 CXX=clang++-14 cmake -S . -B "$sanitizer_build" -G Ninja -DEMLT_SANITIZE=ON -DEMLT_FUZZ=ON \
    -DEMLT_WITH_MPI=OFF -DEMLT_WITH_PYTHON=OFF -DEMLT_BUILD_BENCH=OFF -DEMLT_BUILD_STATISTICAL_TESTS=OFF \
    -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -gline-tables-only" >/dev/null
}
