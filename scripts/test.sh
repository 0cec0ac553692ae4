#!/usr/bin/env bash
# The whole test suite on an existing build: unit tests ([cpu], [gl], [slow]) through CTest,
# the examples, an install + find_package(welkin) consumer build, and the sanitizer build's
# fast tests. Usage: scripts/test.sh BUILD_DIR
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$here/build}
jobs=${WELKIN_JOBS:-$(nproc)}
start=$(date +%s)

echo "== unit tests"
ctest --test-dir "$build" --output-on-failure

echo "== examples"
"$build/bin/example_embed_headless" "$build/example-embed.png"
"$build/bin/example_custom_element" "$build/example-custom.png"

echo "== install and find_package(welkin) from the prefix"
prefix=$(mktemp -d)
cmake --install "$build" --prefix "$prefix" >/dev/null
cmake -S "$here/examples/consumer" -B "$build/consumer" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$build/consumer" -j "$jobs" >/dev/null
"$build/consumer/welkin_consumer"
rm -rf "$prefix"

echo "== sanitizers (ASan + UBSan): fast tests"
san=${WELKIN_SAN_BUILD_DIR:-$build-asan}
cmake -S "$here" -B "$san" -DCMAKE_BUILD_TYPE=Debug -DWELKIN_SANITIZE=ON -DWELKIN_BUILD_EXAMPLES=OFF >/dev/null
cmake --build "$san" -j "$jobs" >/dev/null
# llvmpipe and Mesa leak by design at exit; leaks in welkin's own code are caught by valgrind runs.
ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1 "$san/tests/welkin_tests" "[cpu]~[slow],[gl]~[slow]"

echo "== all tests passed in $(( $(date +%s) - start )) s"
