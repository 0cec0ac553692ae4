#!/usr/bin/env bash
# Does the library build and pass its tests with one element folder deleted? (issue 24, "Done when")
#
#   scripts/element-removal.sh                  # every element folder but the Sky's, one at a time
#   scripts/element-removal.sh grid stars       # these only
#   scripts/element-removal.sh --together       # every element folder but the Sky's, all at once
#   BUILD=/path/to/dir scripts/element-removal.sh grid   # another build directory (default: build-rm)
#
# For each NAME: moves skyelements/NAME out of the tree (to a temporary directory), configures and
# builds every target in a build directory of its own (build-rm, reused from one removal to the
# next: with ccache only what the removal changed compiles), runs the tests the removal can reach,
# and moves the folder back — also when a step fails or the script is interrupted (a trap). The
# tests run: [cpu]~[slow] (all of them, every folder's), the [gl]~[slow] tests of tests/engine/
# and tests/apps/ (the CLI, the framework, the host paths: the ones that name elements), and the
# [gl]~[slow] tests of any test file that guards cases on WELKIN_HAS_ELEMENT_NAME (the removed
# element's dependants, which keep their other cases). Not the whole [gl] suite: the other
# folders' tests do not see the removed one (they reach elements only through the registry).
# With --together the named folders (default: every element but the Sky) are removed at once and
# the tree is built and tested once without all of them: CI's step (scripts/test.sh), about 6
# minutes, since one removal at a time (seven builds) does not fit CI's time. What the combined
# removal does not show, a case guarded on one element that needs another at run time, the
# one-at-a-time runs show: run them after changing what tests or apps ask of the elements (the
# last run is in docs/ci.md). Exit status: 0 when every removal built and passed.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BUILD:-$here/build-rm}
jobs=${JOBS:-$(nproc)}

together=""
if [ "${1:-}" = "--together" ]; then together=1; shift; fi
names=("$@")
if [ ${#names[@]} -eq 0 ]; then
  for dir in "$here"/skyelements/*/; do
    n=$(basename "$dir")
    [ "$n" = sky ] && continue       # the Sky is read by the others (and by the engine's tests)
    [ -d "$dir/src" ] || continue    # not an element folder
    [ "$n" = registry ] && continue  # skyelements/registry is the generated registry, not an element
    names+=("$n")
  done
fi
for n in "${names[@]}"; do
  [[ "$n" =~ ^[a-z][a-z0-9_]*$ ]] || { echo "element-removal.sh: '$n' is not an element name ([a-z][a-z0-9_]*)" >&2; exit 2; }
  [ "$n" != sky ] || { echo "element-removal.sh: the Sky's folder stays (other elements read it)" >&2; exit 2; }
  [ "$n" != registry ] || { echo "element-removal.sh: skyelements/registry is not an element" >&2; exit 2; }
  [ -d "$here/skyelements/$n/src" ] || { echo "element-removal.sh: no element folder skyelements/$n" >&2; exit 2; }
done

stash=$(mktemp -d "${TMPDIR:-/tmp}/welkin-element-removal.XXXXXX")
moved=""   # the folders now in $stash, space-separated
restore() {
  for m in $moved; do
    if [ -d "$stash/$m" ]; then mv "$stash/$m" "$here/skyelements/$m" && echo "restored skyelements/$m"; fi
  done
  moved=""
}
trap 'restore; rmdir "$stash" 2>/dev/null || true' EXIT
trap 'exit 130' INT TERM

launcher=()
if command -v ccache >/dev/null 2>&1; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
tests_bin="$build/tests/welkin_tests"
failed=()
# One run per element, or (--together) one run without all of them; a run's label names its
# removed folders joined by '+'.
runs=()
if [ -n "$together" ]; then runs=("$(IFS=+; echo "${names[*]}")"); else runs=("${names[@]}"); fi
for n in "${runs[@]}"; do
  start=$(date +%s)
  label=$n; [ -z "$together" ] || label=together
  echo "== without skyelements/{${n//+/,}}"
  mkdir -p "$build"
  for m in ${n//+/ }; do
    mv "$here/skyelements/$m" "$stash/$m"
    moved="$moved $m"
  done
  ok=1
  if cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" >"$build/removal-$label.configure.log" 2>&1 &&
     cmake --build "$build" -j"$jobs" >"$build/removal-$label.build.log" 2>&1; then
    grep "cases that need element" "$build/removal-$label.configure.log" | sed 's/^-- /   /' || true
    # The [gl] tests of tests/engine, tests/apps and of every file that guards on this element,
    # by file (Catch2's -# tags each case with its file's name).
    files=$( { ls "$here"/tests/engine/*.cpp "$here"/tests/apps/*.cpp
               for m in ${n//+/ }; do
                 grep -rl --include='*.cpp' "WELKIN_HAS_ELEMENT_$m\b" "$here/tests" "$here"/skyelements/*/tests 2>/dev/null || true
               done; } |
             xargs -n1 basename | sed 's/\.cpp$//' | sort -u)
    spec=""
    for f in $files; do spec+="${spec:+,}[gl]~[slow][#$f]"; done
    if ! "$tests_bin" "[cpu]~[slow]" >"$build/removal-$label.cpu.log" 2>&1; then ok=0; echo "   [cpu]~[slow] failed: $build/removal-$label.cpu.log"; fi
    if ! "$tests_bin" -# "$spec" >"$build/removal-$label.gl.log" 2>&1; then ok=0; echo "   [gl] of tests/engine, tests/apps and the dependants failed: $build/removal-$label.gl.log"; fi
    for log in "$build/removal-$label.cpu.log" "$build/removal-$label.gl.log"; do tail -n 3 "$log" | grep -E "passed|failed" | sed 's/^/   /' || true; done
  else
    ok=0
    echo "   configure or build failed: $build/removal-$label.configure.log, $build/removal-$label.build.log"
    tail -n 20 "$build/removal-$label.build.log" 2>/dev/null | sed 's/^/   /' || true
  fi
  restore
  echo "   ($(( $(date +%s) - start )) s)"
  [ "$ok" = 1 ] || failed+=("$n")
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "element-removal.sh: failed without: ${failed[*]}"
  exit 1
fi
echo "element-removal.sh: every removal built and passed (${names[*]})"
