#!/usr/bin/env bash
# Which files outside its own folder did each element's commits change? (issue 24 item 2)
#
#   scripts/element-footprint.sh                 # commits since issue 24 item 1 landed (df1b769)
#   scripts/element-footprint.sh SINCE           # commits after SINCE (a commit) only
#   scripts/element-footprint.sh --all           # the whole history
#   scripts/element-footprint.sh --check [SINCE] # exit 1 if any element's commit changed a file outside it
#   scripts/element-footprint.sh --static [--check]  # the tree as it stands, not its history:
#       which files outside each folder need, use (guarded), cite or link the element
#       (scripts/element-footprint-static.py; --check: exit 1 when an element but the Sky is needed)
#
# The default SINCE, df1b769, merged element-private GL bindings (issue 24 item 1): from there on
# no element needed the shared binding table. For every folder skyelements/<name>/ it takes the
# commits (merges left out: their changes are their parents') that changed a file inside the
# folder and, for those that also changed files outside it, prints the commit, its subject and
# those files (the first few). A commit that changed several element folders at once is marked
# [several elements] (a change to the framework swept through them) and counts for each. Output:
# one section per element, "name: N of M commits changed files outside skyelements/name/", or
# "name: none (M commits, all inside skyelements/name/)" when it kept to its folder.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
if [ "${1:-}" = "--static" ]; then shift; exec python3 "$here/scripts/element-footprint-static.py" "$@"; fi
check=""
if [ "${1:-}" = "--check" ]; then check=1; shift; fi
since=df1b769
if [ "${1:-}" = "--all" ]; then since=""; shift
elif [ $# -ge 1 ]; then since=$1; shift; fi
if [ $# -gt 0 ]; then echo "element-footprint.sh: one revision (or --all) at most" >&2; exit 2; fi
range=()
if [ -n "$since" ]; then
  git -C "$here" rev-parse --verify -q "$since^{commit}" >/dev/null || { echo "element-footprint.sh: '$since' is not a commit" >&2; exit 2; }
  range=("$since..HEAD")
fi
outside_total=0
if [ -n "$since" ]; then echo "commits after $(git -C "$here" log -1 --format='%h (%cs) %s' "$since" | cut -c1-100)"; else echo "the whole history"; fi
for dir in "$here"/skyelements/*/; do
  name=$(basename "$dir")
  [ "$name" = registry ] && continue  # the elements' registry (welkin/elements/registry.hpp), not an element
  [ -d "$dir/src" ] || continue         # an element folder has its sources
  mapfile -t commits < <(git -C "$here" log --no-merges --format=%H "${range[@]}" -- "skyelements/$name/")
  [ ${#commits[@]} -gt 0 ] || { echo "$name: none (no commits)"; continue; }
  n_out=0
  report=""
  for c in "${commits[@]}"; do
    changed=$(git -C "$here" show --no-renames --format= --name-only "$c")
    out=$(printf '%s\n' "$changed" | sed '/^$/d' | grep -v "^skyelements/$name/" || true)
    [ -n "$out" ] || continue
    n_out=$((n_out + 1))
    elems=$(printf '%s\n' "$changed" | sed -n 's|^skyelements/\([a-z0-9_]*\)/.*|\1|p' | grep -vx registry | sort -u | wc -l)
    mark=""; [ "$elems" -gt 1 ] && mark=" [several elements]"
    n_files=$(printf '%s\n' "$out" | wc -l)
    first=$(printf '%s\n' "$out" | head -n 4 | paste -sd, - | sed 's/,/, /g')
    [ "$n_files" -gt 4 ] && first+=", ... ($n_files files)"
    report+="  $(git -C "$here" log -1 --format='%h %s' "$c" | cut -c1-90)$mark"$'\n'"      $first"$'\n'
  done
  if [ "$n_out" -eq 0 ]; then
    echo "$name: none (${#commits[@]} commits, all inside skyelements/$name/)"
  else
    echo "$name: $n_out of ${#commits[@]} commits changed files outside skyelements/$name/"
    printf '%s' "$report"
  fi
  outside_total=$((outside_total + n_out))
done
if [ -n "$check" ] && [ "$outside_total" -gt 0 ]; then exit 1; fi
exit 0
