#!/usr/bin/env bash
# Regenerates the keys tables of the docs from `welkin vars --markdown --keys-of` (issue 24 item 2):
# docs/keys.md (the engine's keys: a scene with no element) and skyelements/<name>/keys.md for
# every element folder (the keys a scene of that element alone has beyond the engine's).
#
#   scripts/keys-tables.sh                 # with build/bin/welkin
#   scripts/keys-tables.sh path/to/welkin  # another build's command
#
# Each file keeps its text above the line starting `| key |`; the table from there to the end is
# replaced. A folder without keys.md gets one with a short heading. The test "Keys tables" (tag
# [docs]) fails, naming the file and this script, when a table is stale or missing.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
welkin=${1:-$here/build/bin/welkin}
[ -x "$welkin" ] || { echo "keys-tables.sh: no welkin command at $welkin (build it, or give its path)" >&2; exit 2; }
write_table() {  # FILE TABLE-TEXT HEADING-IF-NEW
  local file=$1 table=$2 heading=$3 tmp
  tmp=$(mktemp "$file.XXXXXX")
  if [ -f "$file" ] && grep -q '^| key |' "$file"; then
    sed '/^| key |/,$d' "$file" > "$tmp"
  else
    printf '%s\n\n' "$heading" > "$tmp"
  fi
  printf '%s\n' "$table" >> "$tmp"
  mv "$tmp" "$file"
}
write_table "$here/docs/keys.md" "$("$welkin" vars --markdown --keys-of engine)" "# SkyVars keys"
for dir in "$here"/skyelements/*/; do
  name=$(basename "$dir")
  [ "$name" = registry ] && continue
  [ -d "$dir/src" ] || continue
  write_table "$dir/keys.md" "$("$welkin" vars --markdown --keys-of "$name")" \
"# Keys of the \`$name\` element

The SkyVars keys that a scene with this element alone has beyond the engine's (those are in
\`docs/keys.md\`): its options, what it and the generators it attaches read and write. The table is
the output of \`welkin vars --markdown --keys-of $name\`; a test fails when it is stale: regenerate
it with \`scripts/keys-tables.sh\`."
  echo "keys-tables.sh: skyelements/$name/keys.md"
done
echo "keys-tables.sh: docs/keys.md"
