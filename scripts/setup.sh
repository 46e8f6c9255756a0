#!/usr/bin/env bash
# Installs emlt's build dependencies (Debian packages), builds Release into build/ and makes
# the Python module importable (`import emlt`) by the system python3 from any directory.
# Safe to re-run: packages already present are not reinstalled, the build is incremental.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake ninja-build pkg-config ccache
  libembree-dev libopenexr-dev libtbb-dev libglm-dev libtinyobjloader-dev
  nlohmann-json3-dev libcli11-dev libfmt-dev libstb-dev libjpeg-dev libpng-dev libpugixml-dev zlib1g-dev
  libgtest-dev libbenchmark-dev
  libopenmpi-dev openmpi-bin  # mpirun -n R emlt render ... (optional: EMLT_WITH_MPI)
  clang-14 libclang-rt-14-dev  # libFuzzer targets (scripts/fuzz.sh)
  python3 python3-numpy python3-matplotlib
  python3-dev pybind11-dev python3-tqdm  # the Python module, import emlt, and its progress bar
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq "${missing[@]}"
fi

# The module's packages are installed above: on, even where an earlier configure without
# pybind11 left it off.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DEMLT_WITH_PYTHON=ON
cmake --build build -j "$(nproc)"
echo "setup: built build/emlt"

# `import emlt`: a .pth file in the user's site-packages puts build/python on the system
# python3's path (a re-run from another clone points it there instead).
if compgen -G "build/python/emlt*.so" >/dev/null; then
  # `-m site --user-site` fails when the user site-packages are off (PYTHONNOUSERSITE).
  if site=$(/usr/bin/python3 -m site --user-site); then
    mkdir -p "$site"
    echo "$PWD/build/python" >"$site/emlt.pth"
    if ! (cd / && /usr/bin/python3 -c "import emlt"); then
      echo "setup: python3 does not import emlt through $site/emlt.pth" >&2
      exit 1
    fi
    echo "setup: import emlt from $PWD/build/python ($site/emlt.pth)"
  else
    echo "setup: python3's user site-packages are off: import emlt with" \
      "PYTHONPATH=$PWD/build/python" >&2
  fi
fi
