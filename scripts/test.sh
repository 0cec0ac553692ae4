#!/usr/bin/env bash
# The whole test suite on an existing build: unit tests ([cpu], [gl], [slow]) through CTest,
# the examples, an install (its headers self-contained) + find_package(welkin) and pkg-config
# consumer builds, the API reference (Doxygen), the sanitizer build's fast tests (with the element
# template examples/elements/halo copied into skyelements/ for that build), and a short
# fixed run of the libFuzzer targets (clang; WELKIN_FUZZ_SECONDS per target, default 4), and
# last the tree without its element folders (all but the Sky's, at once: scripts/element-removal.sh).
# Usage: scripts/test.sh [--nightly] BUILD_DIR
#   --nightly (or WELKIN_NIGHTLY=1): the sanitizer step runs the whole suite, [slow] included,
#   under ASan + UBSan with LeakSanitizer on (scripts/lsan.supp); too long for CI's 45 minutes on
#   2 cores, so CI runs the fast tests there instead (docs/ci.md: each step's measured time).
# Each step prints its wall time; the end prints the CPU time of everything the script ran.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
nightly=${WELKIN_NIGHTLY:-}
if [ "${1:-}" = "--nightly" ]; then nightly=1; shift; fi
build=${1:-$here/build}
jobs=${WELKIN_JOBS:-$(nproc)}
start=$(date +%s)
step_name=""
step_start=$start
# step NAME: ends the previous step (printing its wall time) and starts NAME.
step() {
  local now
  now=$(date +%s)
  [ -z "$step_name" ] || echo "   ($step_name: $((now - step_start)) s)"
  step_name=$1
  step_start=$now
  [ -z "$step_name" ] || echo "== $step_name"
}

step "unit tests"
# Two at a time: the three CTest entries (cpu, gl, slow) are single processes that each keep
# about one core busy, so on 2 cores cpu and slow run beside gl.
ctest --test-dir "$build" --output-on-failure -j "$jobs"

step "examples"
"$build/bin/example_embed_headless" "$build/example-embed.png"
"$build/bin/example_custom_element" "$build/example-custom.png"
"$build/bin/example_astro_only" >/dev/null  # welkin::astro alone, no GL

step "install and find_package(welkin) from the prefix"
prefix=$(mktemp -d)
cmake --install "$build" --prefix "$prefix" >/dev/null
# Installed headers include only installed headers and compile with the prefix's flags alone.
"$here/scripts/check-installed-headers.sh" "$prefix"
cmake -S "$here/examples/consumer" -B "$build/consumer" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$build/consumer" -j "$jobs" >/dev/null
"$build/consumer/welkin_consumer"
"$build/consumer/welkin_astro_consumer" >/dev/null

step "examples/host copied out of the tree, built against the installed welkin, one headless frame"
hostsrc=$(mktemp -d)
cp -r "$here/examples/host/." "$hostsrc"
cmake -S "$hostsrc" -B "$hostsrc/build" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$hostsrc/build" -j "$jobs" >/dev/null
"$hostsrc/build/welkin_host" --headless --time 2026-06-21T13:00:00+02:00 --size 320x180 --out "$build/example-host.png"
test -s "$build/example-host.png"
rm -rf "$hostsrc"

step "pkg-config: programs built with 'pkg-config --cflags --libs welkin' (and welkin-astro) from the prefix"
pc_file=$(find "$prefix" -path '*/pkgconfig/welkin.pc' -print -quit)
[ -n "$pc_file" ] || { echo "pkg-config step: no welkin.pc installed under $prefix" >&2; exit 1; }
pc_flags=$(PKG_CONFIG_PATH=$(dirname "$pc_file") pkg-config --cflags --libs welkin)
# shellcheck disable=SC2086  # a list of flags
${CXX:-c++} -std=c++20 "$here/examples/consumer/pkg_config_main.cpp" $pc_flags -o "$build/welkin_pkg_config"
"$build/welkin_pkg_config"
# The astronomy alone: welkin-astro.pc names no GL library, so a GL symbol reached fails the link.
astro_flags=$(PKG_CONFIG_PATH=$(dirname "$pc_file") pkg-config --cflags --libs welkin-astro)
# shellcheck disable=SC2086  # a list of flags
${CXX:-c++} -std=c++20 "$here/examples/astro_only/main.cpp" $astro_flags -o "$build/welkin_astro_pkg_config"
"$build/welkin_astro_pkg_config" >/dev/null
rm -rf "$prefix"

step "API reference: Doxygen over the installed headers, warnings are errors"
"$here/scripts/docs.sh" "$build" >/dev/null

san=${WELKIN_SAN_BUILD_DIR:-$build-asan}
if [ -n "$nightly" ]; then
  step "sanitizers (ASan + UBSan + LeakSanitizer): the whole suite, with the element template in skyelements/"
else
  step "sanitizers (ASan + UBSan): fast tests, with the element template in skyelements/"
fi
# The element template: a new element is one folder. examples/elements/halo is copied into
# skyelements/ (and nothing else may change) before the sanitizer build, so that this build and its
# tests - the whole step's suite, the keys tables' test included - run with the template in place;
# then its render with an option set by --var and `welkin vars` on the same build. No second
# build of the tree for it. Removed again at the end of the step (and on any failure).
tmpl="$here/skyelements/halo"
if [ -e "$tmpl" ]; then echo "skyelements/halo already exists" >&2; exit 1; fi
cleanup_template() { rm -rf "$tmpl"; cmake -S "$here" -B "$san" >/dev/null 2>&1 || true; }
trap cleanup_template EXIT
cp -r "$here/examples/elements/halo" "$tmpl"
if git -C "$here" rev-parse >/dev/null 2>&1; then
  changed=$(git -C "$here" status --porcelain --untracked-files=all | grep -v "^?? skyelements/halo/" || true)
  if [ -n "$changed" ] && [ -z "${WELKIN_ALLOW_DIRTY:-}" ]; then echo "template step: files other than skyelements/halo changed:" >&2; echo "$changed" >&2; exit 1; fi
fi
# -O0 with line tables only (-g1): enough for the reports' stack traces, and the build is the
# longest step (full -g costs about 10% more compile time, -O1 twice as much under ASan).
# The built-in image codec (WELKIN_IMAGE_IO=builtin: stb and welkin's own EXR) instead of
# OpenImageIO: the tests start the CLI a few hundred times, and each start of a binary linked
# with OpenImageIO's ~270 shared libraries spends ~2 s of CPU in the dynamic loader under ASan
# (LD_DEBUG=statistics: 160k symbol lookups through every library); the Release build above
# tests OpenImageIO, and test_image_io checks the two codecs against each other.
cmake -S "$here" -B "$san" -DCMAKE_BUILD_TYPE=Debug -DWELKIN_SANITIZE=ON -DWELKIN_BUILD_EXAMPLES=OFF \
  -DWELKIN_IMAGE_IO=builtin -DCMAKE_CXX_FLAGS_DEBUG=-g1 -DCMAKE_C_FLAGS_DEBUG=-g1 >/dev/null
cmake --build "$san" -j "$jobs" >/dev/null
export UBSAN_OPTIONS=print_stacktrace=1
# LeakSanitizer on in the nightly run: welkin's own leaks fail it; scripts/lsan.supp lists the
# Mesa/EGL ones. The CLI runs the tests start inherit these options (built with the sanitizers too).
if [ -n "$nightly" ]; then
  san_env=(ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS="suppressions=$here/scripts/lsan.supp:print_suppressions=0")
else
  san_env=(ASAN_OPTIONS=detect_leaks=0)
fi
# The template in this build: it renders with its option set by --var, `welkin vars` lists its
# keys, and its own test is among the tests below.
env "${san_env[@]}" "$san/bin/welkin" render --time 2026-06-21T10:00:00Z --lat 48 --lon 2 --elements sky,halo --projection fisheye \
  --size 128x128 --var halo.radius_rad=22deg --var halo.gain_per_sr=0.05 --out "$san/template-halo.png"
env "${san_env[@]}" "$san/bin/welkin" vars --elements halo --json > "$san/template-vars.json"
grep -q '"halo.gain_per_sr"' "$san/template-vars.json"
# One start of the command with LeakSanitizer on, in CI too: every subcommand and bench registers
# its options at start-up, so an option struct leaked by a registrar fails here (the nightly run
# found four); `vars` needs no GL, so the driver's own allocations do not enter.
ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS="suppressions=$here/scripts/lsan.supp:print_suppressions=0" \
  "$san/bin/welkin" vars --elements sky >/dev/null
{ env "${san_env[@]}" "$san/tests/welkin_tests" "[halo]" --list-test-names-only || true; } | grep -q . ||
  { echo "template step: the sanitizer build's tests hold no [halo] test" >&2; exit 1; }
# The test binary runs as two processes side by side: one process keeps about one core busy
# (the [cpu] tests and the CLI runs are single-threaded, llvmpipe's shader compiles too), so on
# CI's 2 cores the pair takes about the longer one's time. Under ASan the [gl] tests take about
# 2.7x the [cpu] ones (measured: 13.5 and 5 min), so the first process runs the [cpu] tests and
# every third [gl] test, the second the other two thirds. Each gets its tests by name through
# Catch2's --input-file (whose lines are names, not tag expressions: the names are listed from
# the binary each run, so a new test always runs in one of the two, and Catch2's special
# characters in them , [ ] * \ " ~ are escaped with a backslash).
# run_halves OPTIONS... : both with the environment given, each to its own log; both logs
# printed; fails if either fails, or if the two lists do not hold every test of the step.
run_halves() {
  local pids=() rc=0 logs=("$san/sanitizer-1.log" "$san/sanitizer-2.log") i
  local first="[cpu]~[slow]" rest="[gl]~[slow]"
  if [ -n "$nightly" ]; then first="[cpu]" rest="~[cpu]"; fi  # nightly: everything, [slow] included
  local esc='s/[][,*\\"~]/\\&/g'
  # (Catch2 exits with the number of tests a --list option found: its status is not an error.)
  { env "$@" "$san/tests/welkin_tests" "$first" --list-test-names-only || true; } | sed '/^$/d' >"$san/sanitizer-first.txt"
  { env "$@" "$san/tests/welkin_tests" "$rest" --list-test-names-only || true; } | sed '/^$/d' >"$san/sanitizer-rest.txt"
  { cat "$san/sanitizer-first.txt"; awk 'NR % 3 == 1' "$san/sanitizer-rest.txt"; } | sed "$esc" >"$san/sanitizer-1.txt"
  awk 'NR % 3 != 1' "$san/sanitizer-rest.txt" | sed "$esc" >"$san/sanitizer-2.txt"
  local want have
  want=$(cat "$san/sanitizer-first.txt" "$san/sanitizer-rest.txt" | wc -l)
  have=$(for i in 1 2; do
           if [ -s "$san/sanitizer-$i.txt" ]; then env "$@" "$san/tests/welkin_tests" --input-file "$san/sanitizer-$i.txt" --list-test-names-only || true; fi
         done | sed '/^$/d' | sort -u | wc -l)
  if [ "$want" -eq 0 ] || [ "$want" != "$have" ]; then
    echo "sanitizer step: the two name lists select $have tests of $want (none listed: the binary failed to list them)" >&2
    return 1
  fi
  for i in 0 1; do
    # (An empty list would mean "every test" to Catch2.)
    [ -s "$san/sanitizer-$((i + 1)).txt" ] || continue
    env "$@" "$san/tests/welkin_tests" --input-file "$san/sanitizer-$((i + 1)).txt" >"${logs[$i]}" 2>&1 &
    pids+=($!)
  done
  for i in "${!pids[@]}"; do
    if ! wait "${pids[$i]}"; then rc=1; cat "${logs[$i]}"; else tail -n 2 "${logs[$i]}"; fi
  done
  return $rc
}
run_halves "${san_env[@]}"
cleanup_template  # (the sanitizer tree is rebuilt without the template by its next build)
trap - EXIT

step "fuzzing: the libFuzzer targets' saved crash inputs, then each target ${WELKIN_FUZZ_SECONDS:-4} s from its seeds"
# Builds only the engine and the fuzz targets (clang, -O1, ASan + UBSan + libFuzzer; docs/fuzzing.md).
# A fixed short run: 10 targets x 4 s plus the replays, about a minute; scripts/fuzz.sh 300 runs long.
FUZZ_BUILD_DIR=${WELKIN_FUZZ_BUILD_DIR:-$build-fuzz} FUZZ_JOBS=$jobs FUZZ_SEED=${FUZZ_SEED:-1} "$here/scripts/fuzz.sh" "${WELKIN_FUZZ_SECONDS:-4}"

step "element folders removed: every element folder but the Sky's deleted at once, the tree builds and passes"
# An element is one folder (issue 24): with skyelements/<name> gone for every element but the Sky
# (which the others read), nothing else changed, the library, the command and the tests build and
# the tests that can reach the elements pass (scripts/element-removal.sh --together: [cpu]~[slow],
# the [gl] tests of tests/engine, tests/apps and of every file with cases guarded on a removed
# element). It reuses the Release build folder (only what the removal changes recompiles), so it
# runs last; the folders are moved back when it ends, also on failure. One removal at a time is
# the same script without --together (seven builds: docs/ci.md has the last run).
BUILD="$build" JOBS="$jobs" "$here/scripts/element-removal.sh" --together
step ""

echo "== all tests passed in $(( $(date +%s) - start )) s; CPU time (user system) of the script, then of what it ran:"
times
