#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz, docs/fuzzing.md) with clang in build-fuzz/ and runs
# each for a fixed time from its seed corpus, after replaying the saved crash inputs
# (tests/fuzz/regressions/<target>/; an element's own targets keep theirs in its folder:
# skyelements/<name>/fuzz/corpus/<target>/ and .../fuzz/regressions/<target>/).
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]      default 10 s, every target
# Environment: FUZZ_BUILD_DIR (build-fuzz), FUZZ_WORK_DIR (a temporary folder: the corpus each run
# grows and any crash input, kept when something is found), FUZZ_JOBS (build jobs, nproc), FUZZ_SEED
# (libFuzzer's -seed; unset: a random one).
# Exit status: 0 when no target found anything, 1 otherwise (the input that did is named).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-10}
shift || true
build=${FUZZ_BUILD_DIR:-build-fuzz}
jobs=${FUZZ_JOBS:-$(nproc)}
command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ not found (Debian package clang)" >&2; exit 2; }

cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DWELKIN_FUZZ=ON >/dev/null
cmake --build "$build" -j"$jobs" --target welkin_fuzz

work=${FUZZ_WORK_DIR:-$(mktemp -d -t welkin-fuzz.XXXXXX)}
mkdir -p "$work"
# Sanitizer reports end the run (any finding is fatal); symbolised stacks.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:symbolize=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/fuzz/lsan.supp}  # OpenImageIO's own leak
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for t in "$build"/fuzz/fuzz_*; do targets+=("$(basename "$t")"); done
fi
# The folder holding a target's corpus/ and regressions/: tests/fuzz, or the element folder's fuzz/
# whose fuzz_*.cpp defines it.
data_dir() {
  local d
  for d in skyelements/*/fuzz; do
    [ -f "$d/$1.cpp" ] && { echo "$d"; return; }
  done
  echo tests/fuzz
}
failed=()
for t in "${targets[@]}"; do
  bin="$build/fuzz/$t"
  [ -x "$bin" ] || { echo "fuzz.sh: no target $t" >&2; exit 2; }
  data=$(data_dir "$t")
  # 1. The saved crash inputs: each must now pass.
  if compgen -G "$data/regressions/$t/*" >/dev/null; then
    if ! "$bin" "$data"/regressions/"$t"/* >"$work/$t.regressions.log" 2>&1; then
      echo "FAIL $t: a saved regression input fails again (log: $work/$t.regressions.log)"
      failed+=("$t")
      continue
    fi
  fi
  # 2. Fuzz from the seeds (copied: the repository's corpus is not changed).
  mkdir -p "$work/$t/corpus"
  cp -n "$data"/corpus/"$t"/* "$work/$t/corpus/" 2>/dev/null || true
  if "$bin" "$work/$t/corpus" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2560 -malloc_limit_mb=2048 \
       ${FUZZ_SEED:+-seed=$FUZZ_SEED} -artifact_prefix="$work/$t/" -print_final_stats=1 >"$work/$t.log" 2>&1; then
    echo "ok   $t: $(grep -E '^stat::number_of_executed_units' "$work/$t.log" | awk '{print $2}') runs in ${seconds} s"
  else
    echo "FAIL $t: $(ls "$work/$t"/crash-* "$work/$t"/leak-* "$work/$t"/timeout-* "$work/$t"/oom-* 2>/dev/null | head -1) (log: $work/$t.log)"
    failed+=("$t")
  fi
done
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz.sh: ${#failed[@]} target(s) found something: ${failed[*]} (inputs and logs in $work)"
  exit 1
fi
[ -n "${FUZZ_WORK_DIR:-}" ] || rm -rf "$work"
echo "fuzz.sh: ${#targets[@]} target(s), no finding"
