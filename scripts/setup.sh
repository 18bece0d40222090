#!/usr/bin/env bash
# Installs what oitref needs from Debian 12 packages (only what is missing), then configures and
# builds it in ./build (Release). Safe to run again: it does only what is not done yet.
#   OITREF_BUILD_DIR   build folder (default: build)
#   OITREF_CMAKE_ARGS  extra CMake arguments (e.g. -DOITREF_F16C=OFF)
#   OITREF_BUILD_TARGET  build only these targets, space-separated (default: everything)
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake ninja-build libglm-dev libembree-dev libtbb-dev
          libopenimageio-dev openimageio-tools libimath-dev catch2 libcli11-dev
          libassimp-dev nlohmann-json3-dev zlib1g-dev
          pybind11-dev python3-dev python3-numpy python3-pytest      # import oitref, and its tests
          libegl-dev libgl-dev libegl1 libegl-mesa0 libgl1-mesa-dri  # glcheck: Mesa's llvmpipe
          clang libclang-rt-14-dev                                   # CI: sanitizers, libFuzzer
          chromium fonts-dejavu-core                                 # tests: the study report in a real browser
          slurm-wlm munge)                                           # tests: a study through a one-node Slurm

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "oitref setup: installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

build="${OITREF_BUILD_DIR:-build}"
# shellcheck disable=SC2086
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release ${OITREF_CMAKE_ARGS:-} >/dev/null
# shellcheck disable=SC2086
cmake --build "$build" -j "$(nproc)" ${OITREF_BUILD_TARGET:+--target $OITREF_BUILD_TARGET}
