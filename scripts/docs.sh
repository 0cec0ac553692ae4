#!/usr/bin/env bash
# The API reference (HTML) from the installed public headers, with Doxygen (docs/Doxyfile).
# Any Doxygen warning fails the run (CI: scripts/test.sh). Needs a configured build folder (it
# installs only the headers, so nothing need be compiled); configures one if there is none.
# Usage: scripts/docs.sh [BUILD_DIR]   -> BUILD_DIR/api/html/index.html
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$here/build}
command -v doxygen >/dev/null || { echo "docs.sh: doxygen not found (Debian: apt-get install doxygen)" >&2; exit 1; }
[ -f "$build/cmake_install.cmake" ] || cmake -S "$here" -B "$build" >/dev/null

headers=$(mktemp -d)
trap 'rm -rf "$headers"' EXIT
cmake --install "$build" --component headers --prefix "$headers" >/dev/null
[ -d "$headers/include/welkin" ] || { echo "docs.sh: installing the headers component of $build gave no include/welkin" >&2; exit 1; }

version=$(sed -n 's/^project(welkin VERSION \([0-9.]*\).*/\1/p' "$here/CMakeLists.txt")
rm -rf "$build/api"
mkdir -p "$build/api"
# Doxygen's warnings go to stderr; FAIL_ON_WARNINGS (docs/Doxyfile) makes it exit non-zero.
if ! (cd "$here" && WELKIN_VERSION=$version WELKIN_SOURCE_DIR=$here WELKIN_API_HEADERS=$headers/include \
      WELKIN_API_OUTPUT=$build/api doxygen docs/Doxyfile) 2> "$headers/warnings.txt"; then
  sed "s|$headers/include/||g" "$headers/warnings.txt" >&2
  echo "docs.sh: Doxygen warnings in the public headers (above; fix the /// comments)" >&2
  exit 1
fi
echo "$build/api/html/index.html"
