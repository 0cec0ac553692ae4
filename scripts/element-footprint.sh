#!/usr/bin/env bash
# Which files outside its own folder did each element's commits change? (issue 24 item 2)
#
#   scripts/element-footprint.sh                 # the whole history, every element folder
#   scripts/element-footprint.sh df1b769         # commits after df1b769 only
#   scripts/element-footprint.sh --check df1b769 # exit 1 if any element's commit there changed a file outside it
#
# For every folder skyelements/<name>/ it takes the commits (merges left out: their changes are
# their parents') that changed a file inside the folder, and lists the files outside the folder
# those same commits changed, with how many of the commits did so. A commit that also changed
# another element's folder counts for both. "An element is one folder" holds for an element when
# its list is empty. Output: one section per element, "name: N of M commits changed files outside"
# then the files, most often changed first.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
check=""
if [ "${1:-}" = "--check" ]; then check=1; shift; fi
since=${1:-}
if [ $# -gt 1 ]; then echo "element-footprint.sh: one revision at most (got $#)" >&2; exit 2; fi
range=()
if [ -n "$since" ]; then
  git -C "$here" rev-parse --verify -q "$since^{commit}" >/dev/null || { echo "element-footprint.sh: '$since' is not a commit" >&2; exit 2; }
  range=("$since..HEAD")
fi
outside_total=0
for dir in "$here"/skyelements/*/; do
  name=$(basename "$dir")
  [ "$name" = registry ] && continue  # the elements' registry (welkin/elements/registry.hpp), not an element
  [ -d "$dir/src" ] || continue         # an element folder has its sources
  mapfile -t commits < <(git -C "$here" log --no-merges --format=%H "${range[@]}" -- "skyelements/$name/")
  [ ${#commits[@]} -gt 0 ] || { echo "$name: no commits"; continue; }
  n_out=0
  files=""
  for c in "${commits[@]}"; do
    out=$(git -C "$here" show --no-renames --format= --name-only "$c" | grep -v "^skyelements/$name/" || true)
    if [ -n "$out" ]; then n_out=$((n_out + 1)); files+="$out"$'\n'; fi
  done
  echo "$name: $n_out of ${#commits[@]} commits changed files outside skyelements/$name/"
  if [ -n "$files" ]; then printf '%s' "$files" | sed '/^$/d' | sort | uniq -c | sort -rn | sed 's/^/  /'; fi
  outside_total=$((outside_total + n_out))
done
if [ -n "$check" ] && [ "$outside_total" -gt 0 ]; then exit 1; fi
exit 0
