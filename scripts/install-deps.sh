#!/usr/bin/env bash
# Installs the Debian 12 packages vascsim needs to build, test and plot. Idempotent: packages that are
# already installed are skipped, and apt-get runs only when something is missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev nlohmann-json3-dev libcli11-dev libfmt-dev libspdlog-dev
  libgtest-dev libgmock-dev libbenchmark-dev libassimp-dev libsuitesparse-dev libopenblas0-pthread
  python3 python3-matplotlib python3-numpy python3-meshio
  # render_surface.py --all-frames writes its animated GIF through matplotlib's Pillow writer.
  python3-pil
  # The Python module (VASCSIM_BUILD_PYTHON) and its tests; dpkg-dev's dpkg-shlibdeps for `make package`.
  pybind11-dev python3-dev python3-pytest dpkg-dev
  # The viewer / renderer (VASCSIM_BUILD_VIEWER): windows, GL loading, headless EGL on Mesa's software
  # rasteriser, the HUD, PNG writing; xvfb/xauth for a virtual X display (xvfb-run -a) as a fallback.
  libglfw3-dev libimgui-dev libepoxy-dev libegl-dev libgl-dev libgl1-mesa-dri libegl-mesa0 libstb-dev
  xvfb xauth
  # The sanitizer stages of `make test` and `make fuzz` (libFuzzer, ASan, UBSan, TSan) build with clang, its
  # sanitizer runtimes and its OpenMP runtime (docs/reliability.md).
  clang-14 libclang-rt-14-dev libomp-14-dev
  # The formatting check of `make test` (tests/python/check_format.py) and `make format`: one pinned version.
  clang-format-14
  # `make experiments` fans its independent runs out with GNU parallel (a plain loop without it).
  parallel
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y --no-install-recommends "${missing[@]}"
