#!/bin/bash
# (Unpack the snapshot without its data/ folder: `git archive` of the fetched snapshot stops at
# large example-scene files the snapshot lacks, and the renderer needs none of them.)
# Builds Tungsten's command-line renderer (github.com/tunabrain/tungsten, snapshot 88ea020 of
# 2019-04-14) for bench/tungsten_equal_time.py. Tungsten's code is never committed here: give
# the path of an unpacked snapshot; the build goes to BUILD_DIR (default ./tungsten-build).
#
#   bench/build_tungsten.sh SRC_DIR [BUILD_DIR] [-- NINJA_ARGS]   # then TUNGSTEN=BUILD_DIR/tungsten
#
# Environment: JOBS (default 2), PREFIX (a command put before cmake, e.g. a nice wrapper).
# Choices: Release; OpenEXR, OpenVDB, Eigen and Qt left out (the renderer writes .pfm);
# TARGET_ARCHITECTURE=nehalem (SSE4.2, Tungsten's own ceiling, EMBREE_MAX_ISA), since its
# OptimizeForArchitecture falls back to core2 (SSSE3) on CPUs it does not know by model.
set -euo pipefail
SRC=$(cd "${1:?usage: build_tungsten.sh SRC_DIR [BUILD_DIR] [-- NINJA_ARGS]}" && pwd)
BUILD=${2:-tungsten-build}
shift $(( $# < 2 ? $# : 2 ))
[ "${1:-}" = "--" ] && shift
JOBS=${JOBS:-2}
read -r -a PREFIX <<< "${PREFIX:-}"

# Our patches for GCC 12 (applied to the copy given, idempotent).
PATCHES_APPLIED="$SRC/.emlt-patches-applied"
if [ ! -e "$PATCHES_APPLIED" ]; then
  :  # none needed: the snapshot builds with GCC 12.2 as it is (2026-11-26, warnings only)
  touch "$PATCHES_APPLIED"
fi

mkdir -p "$BUILD"
cd "$BUILD"
"${PREFIX[@]}" cmake -G Ninja "$SRC" -DCMAKE_BUILD_TYPE=Release -DTARGET_ARCHITECTURE=nehalem \
  -DCMAKE_DISABLE_FIND_PACKAGE_OpenEXR=ON -DCMAKE_DISABLE_FIND_PACKAGE_OpenVDB=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_TBB=ON -DCMAKE_DISABLE_FIND_PACKAGE_Eigen3=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_Qt5Widgets=ON -DCMAKE_DISABLE_FIND_PACKAGE_Qt5OpenGL=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_OpenGL=ON > cmake.log
"${PREFIX[@]}" cmake --build . -j "$JOBS" --target tungsten -- "$@"
echo "TUNGSTEN=$(pwd)/tungsten"
