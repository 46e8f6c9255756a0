#!/bin/bash
# Builds pbrt-v4 on Debian 12 as a reference renderer for the pbrt conformance group: CPU only, Release.
# Usage: build-pbrt.sh PBRT_GIT DEST [SUBMODULE_MIRRORS_DIR]
#   PBRT_GIT               a git repository of mmp/pbrt-v4 (the folder that the search tool's fetch prints)
#   DEST                   where to check it out and build; the binary ends up at DEST/build/pbrt
#   SUBMODULE_MIRRORS_DIR  a folder holding the submodules' repositories as OWNER+NAME/repo (the search tool's
#                          fetch layout); default: the folder two levels above PBRT_GIT. Without it (or with a
#                          submodule missing there) the submodule is cloned from GitHub.
# Run it as:     DEST/build/pbrt --nthreads 2 --outfile out.pfm scene.pbrt   (EXR when the name ends in .exr)
# Notes: no CUDA/OptiX (pbrt's CMake only enables the GPU path when it finds both CUDA and PBRT_OPTIX_PATH,
# which is never set here). GLFW is built for its "null" platform only (no X11, no Wayland): pbrt links it for
# the --interactive viewer, which the references never use. The RGB-to-spectrum tables are generated at build
# time by pbrt's own rgb2spec_opt (pbrt's default). Only the pbrt executable is built (no tests, no tools).
# Two pinned submodule commits are missing from the fetched mirrors (double-conversion 101e1ba, zlib 5a82f71):
# those are checked out at the mirror's newest commit, and pbrt's CMake commit check for them is removed; zlib
# is Debian's anyway (pbrt only builds its copy when find_package(ZLIB) fails), and double-conversion only
# parses numbers. The fetched snapshot of pbrt-v4 lacks its two largest files, the data tables
# src/pbrt/util/bluenoise.cpp (blue-noise textures) and pmj02tables.cpp (PMJ02BN point sets): the script
# writes a zero-filled table of the declared size in place of each missing one. Only the "pmj02bn" sampler and
# the dithering of 8-bit outputs (PNG, QOI) read them, so the "pmj02bn" sampler is made to refuse to run; the
# references use the "independent" sampler and float PFM output, which read neither. Nothing that changes such
# an image is patched.
set -eu
SRC=${1:?usage: build-pbrt.sh PBRT_GIT DEST [SUBMODULE_MIRRORS_DIR]}
DEST=${2:?usage: build-pbrt.sh PBRT_GIT DEST [SUBMODULE_MIRRORS_DIR]}
SRC=$(cd "$SRC" && pwd)
MIRRORS=${3:-$(dirname "$(dirname "$SRC")")}
JOBS=${JOBS:-2}
SUDO=; [ "$(id -u)" -eq 0 ] || SUDO=sudo
$SUDO apt-get update -qq
# Debian's OpenEXR (3.1.5; pbrt wants 3.1.1 or newer) instead of the submodule, whose fetched mirror lacks
# one of its files (OpenEXRCore/dwaLookups.h)
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq cmake g++ git zlib1g-dev libgl-dev libopenexr-dev \
  >/dev/null
[ -d "$DEST/.git" ] || git clone -q --no-checkout "$SRC" "$DEST"
cd "$DEST"
# checks out COMMIT in the repository DIR except the files whose blobs the snapshot lacks, listed in DIR/.missing-blobs
checkout_present() {
  local dir=$1 commit=$2
  git -C "$dir" ls-tree -r "$commit" | awk -F'\t' '{ split($1, a, " "); if (a[2] == "blob") print a[3] "\t" $2 }' \
    > "$dir/.blobs"
  cut -f1 "$dir/.blobs" | git -C "$dir" cat-file --batch-check='%(objectname) %(objecttype)' | paste - "$dir/.blobs" \
    | awk -F'\t' '$1 ~ / missing$/ { print $3 }' > "$dir/.missing-blobs"
  git -C "$dir" read-tree "$commit"
  git -C "$dir" ls-tree -r --name-only "$commit" | grep -vxF -f "$dir/.missing-blobs" \
    | git -C "$dir" checkout-index --stdin -f
  git -C "$dir" update-ref --no-deref HEAD "$commit"
}
checkout_present . HEAD
for path in $(cat .missing-blobs); do
  case "$path" in
    src/pbrt/util/bluenoise.cpp)
      printf '%s\n' '// zero-filled stand-in written by build-pbrt.sh: the snapshot lacks the real table' \
        '#include <pbrt/util/bluenoise.h>' 'namespace pbrt {' \
        'PBRT_CONST uint16_t BlueNoiseTextures[NumBlueNoiseTextures][BlueNoiseResolution][BlueNoiseResolution] = {};' \
        '}' > "$path" ;;
    src/pbrt/util/pmj02tables.cpp)
      printf '%s\n' '// zero-filled stand-in written by build-pbrt.sh: the snapshot lacks the real table' \
        '#include <pbrt/util/pmj02tables.h>' 'namespace pbrt {' \
        'PBRT_CONST uint32_t pmj02bnSamples[nPMJ02bnSets][nPMJ02bnSamples][2] = {};' '}' > "$path"
      # the sampler that reads the table refuses to run rather than render with a zero table
      sed -i '/^PMJ02BNSampler \*PMJ02BNSampler::Create(/,/^ *const FileLoc \*loc, Allocator alloc) {/{
/Allocator alloc) {/a\    ErrorExit(loc, "this pbrt was built by build-pbrt.sh without the PMJ02BN tables: use another sampler");
}' src/pbrt/samplers.cpp
      grep -q 'without the PMJ02BN tables' src/pbrt/samplers.cpp \
        || { echo "build-pbrt: samplers.cpp patch did not apply"; exit 1; } ;;
    *) echo "build-pbrt: the snapshot lacks $path, which has no stand-in"; exit 1 ;;
  esac
done
# the pinned submodule commits, and where each submodule lives on GitHub
declare -A URL=(
  [ptex]=wdas/ptex [double-conversion]=mmp/double-conversion [stb]=nothings/stb
  [openexr]=AcademySoftwareFoundation/openexr [filesystem]=wjakob/filesystem
  [openvdb]=AcademySoftwareFoundation/openvdb [libdeflate]=mmp/libdeflate [lodepng]=lvandeve/lodepng
  [utf8proc]=JuliaStrings/utf8proc [qoi]=phoboslab/qoi [glfw]=glfw/glfw [zlib]=madler/zlib)
UNPINNED=""
for name in "${!URL[@]}"; do
  pin=$(git ls-tree HEAD "src/ext/$name" | awk '{print $3}')
  dir=src/ext/$name
  if [ ! -e "$dir/.git" ]; then
    rm -rf "$dir"
    mirror="$MIRRORS/${URL[$name]/\//+}/repo"
    if [ -d "$mirror" ]; then git clone -q -s --no-checkout "$mirror" "$dir"
    else git clone -q --no-checkout "https://github.com/${URL[$name]}.git" "$dir"; fi
  fi
  if git -C "$dir" cat-file -e "$pin^{commit}" 2>/dev/null; then
    checkout_present "$dir" "$pin"
  else
    echo "build-pbrt: $name's pinned commit $pin is not in the mirror; using its newest commit"
    checkout_present "$dir" "$(git -C "$dir" rev-parse HEAD)"
    UNPINNED="$UNPINNED $name"
  fi
done
# pbrt's CMake refuses a submodule that is not at its pinned commit; drop that check for the unpinned ones only
for name in $UNPINNED; do
  sed -i "/^check_ext (\"[^\"]*\" \"$name\//d" CMakeLists.txt
done
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPBRT_BUILD_NATIVE_EXECUTABLE=OFF \
  -DGLFW_BUILD_X11=OFF -DGLFW_BUILD_WAYLAND=OFF -DBUILD_TESTING=OFF > cmake.log 2>&1 \
  || { tail -30 cmake.log; echo "build-pbrt: cmake failed (see $DEST/cmake.log)"; exit 1; }
nice -n 15 cmake --build build -j"$JOBS" --target pbrt_exe > build.log 2>&1 \
  || { grep -m5 -B2 -A5 'error' build.log; echo "build-pbrt: build failed (see $DEST/build.log)"; exit 1; }
[ -x build/pbrt ] && echo "build-pbrt: built $DEST/build/pbrt ($(git rev-parse HEAD))"
