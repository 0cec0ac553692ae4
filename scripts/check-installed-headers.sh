#!/usr/bin/env bash
# An installed welkin's headers stand on their own: every welkin header an installed header
# includes is installed too, and each installed header compiles on its own with nothing but
# `pkg-config --cflags welkin` (the prefix's welkin.pc). Internal headers are
# listed in cmake/WelkinHelpers.cmake (WELKIN_INTERNAL_HEADERS); docs/architecture.md, "Installed API".
# Usage: scripts/check-installed-headers.sh PREFIX   (after `cmake --install BUILD --prefix PREFIX`)
set -euo pipefail
prefix=${1:?usage: check-installed-headers.sh PREFIX}
inc=$prefix/include
[ -d "$inc/welkin" ] || { echo "check-installed-headers: no $inc/welkin (install first)" >&2; exit 1; }

mapfile -t headers < <(cd "$inc" && find welkin -type f \( -name '*.hpp' -o -name '*.h' \) | LC_ALL=C sort)
[ ${#headers[@]} -gt 0 ] || { echo "check-installed-headers: no headers under $inc/welkin" >&2; exit 1; }

# 1. Includes of welkin headers resolve inside the prefix: <welkin/...> from the include root,
#    "..." from the including header's folder first, then the include root.
bad=0
for h in "${headers[@]}"; do
  while IFS= read -r line; do
    if [[ $line =~ ^[[:space:]]*#[[:space:]]*include[[:space:]]*\<(welkin/[^>]+)\> ]]; then
      target=${BASH_REMATCH[1]}
      [ -f "$inc/$target" ] && continue
    elif [[ $line =~ ^[[:space:]]*#[[:space:]]*include[[:space:]]*\"([^\"]+)\" ]]; then
      target=${BASH_REMATCH[1]}
      [ -f "$inc/$(dirname "$h")/$target" ] || [ -f "$inc/$target" ] && continue
    else
      continue
    fi
    echo "check-installed-headers: installed header $h includes $target, which is not installed (cmake/WelkinHelpers.cmake: WELKIN_INTERNAL_HEADERS)" >&2
    bad=1
  done < "$inc/$h"
done
[ $bad -eq 0 ] || exit 1

# 2. Each installed header compiles on its own (as the first include of a translation unit) with
#    the installed welkin.pc's flags only: no source tree, no build tree.
pc_dir=$(dirname "$(find "$prefix" -path '*/pkgconfig/welkin.pc' -print -quit)")
[ -f "$pc_dir/welkin.pc" ] || { echo "check-installed-headers: no welkin.pc under $prefix" >&2; exit 1; }
cflags=$(PKG_CONFIG_PATH=$pc_dir${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH} pkg-config --cflags welkin)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export cflags work cxx=${CXX:-c++}
# shellcheck disable=SC2016  # expanded by the inner shell
printf '%s\n' "${headers[@]}" | xargs -P "${WELKIN_JOBS:-$(nproc)}" -I{} bash -c '
  log=$work/$(echo "$1" | tr / _).log
  printf "#include <%s>\n" "$1" | $cxx -std=c++20 -fsyntax-only -Wall -Wextra $cflags -x c++ - > "$log" 2>&1 ||
    echo "$1" >> "$work/failed"' _ {}
if [ -s "$work/failed" ]; then
  first=$(LC_ALL=C sort "$work/failed" | head -1)
  head -20 "$work/$(echo "$first" | tr / _).log" >&2
  while IFS= read -r h; do
    echo "check-installed-headers: installed header $h does not compile on its own with 'pkg-config --cflags welkin'" >&2
  done < <(LC_ALL=C sort "$work/failed")
  exit 1
fi
echo "check-installed-headers: ${#headers[@]} installed headers, each self-contained ($inc)"
