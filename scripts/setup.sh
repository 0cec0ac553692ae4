#!/usr/bin/env bash
# welkin set-up for a fresh Debian 12 machine (root or sudo).
#   scripts/setup.sh render   install what is missing, build, render the default sky (prints the path)
#   scripts/setup.sh test     install what is missing, build, run the whole test suite
# Environment: WELKIN_BUILD_DIR (default: build), WELKIN_JOBS (default: number of cores).
set -euo pipefail
mode=${1:-render}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${WELKIN_BUILD_DIR:-$here/build}
jobs=${WELKIN_JOBS:-$(nproc)}

packages=(build-essential cmake pkg-config git
  libglfw3-dev libglm-dev libopenimageio-dev openimageio-tools catch2 libepoxy-dev libegl-dev
  libegl-mesa0 libgl1-mesa-dri liberfa-dev libcli11-dev nlohmann-json3-dev libimgui-dev glslang-tools
  xvfb xauth kstars-data stellarium-data libfreetype-dev fonts-dejavu-core python3 python3-matplotlib
  doxygen libtinygltf-dev ffmpeg
  clang libclang-rt-14-dev)  # the libFuzzer targets (scripts/fuzz.sh); libFuzzer's runtime is only a Recommends of clang

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "welkin setup: installing ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null ||
    { $sudo apt-get update -q >/dev/null && $sudo apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null; }
fi

build_start=$(date +%s)
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$jobs" >/dev/null
echo "== build (Release): $(( $(date +%s) - build_start )) s" >&2

case "$mode" in
  render)
    mkdir -p "$here/out"
    "$build/bin/welkin" render --time 2026-06-21T19:30:00+02:00 --lat 35.9 --lon 14.5 \
      --projection perspective --az 290 --alt 10 --fov 70 --size 1280x720 --out "$here/out/welkin-default.png"
    ;;
  test)
    exec "$here/scripts/test.sh" "$build"
    ;;
  *)
    echo "usage: scripts/setup.sh render|test" >&2
    exit 2
    ;;
esac
