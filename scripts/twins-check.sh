#!/usr/bin/env bash
# Which functions are written twice, once in a shader and once in C++? (issue 24 item 3: "grep
# finds no duplicated optical function between *.glsl and *.cpp")
#
#   scripts/twins-check.sh          # list every name defined in a *.glsl and in a *.cpp/*.hpp file,
#                                   # then the literals and expressions written in both (below)
#   scripts/twins-check.sh --check  # exit 1 when one is neither shared nor in the allowed list
#   scripts/twins-check.sh --constants  # leads for copies the name check cannot see (below)
#
# A function is "defined" in a file when a line of it reads `TYPE NAME(` at the start of a
# declaration (GLSL: a top-level line; C++: any line whose first word is not a statement keyword).
# Names are compared after dropping the shaders' family prefixes (atm_, cld_, welkin_, pp_,
# planet_, rainbow_, night_, stars_, lighting_, clouds_) and case, so `atm_segmentFactor` and a
# C++ `segmentFactor` are one name. The `*.shared.glsl` files are the one source both languages
# compile (docs/architecture.md, "One source for the GPU maths"): they count as shaders, so a C++
# function named like a shared one is listed too (a wrapper that calls it, or a copy). `main` and
# the C++ of tests and benches (which compare the twins, they hold none) are left out.
#
# scripts/twins-allowed.txt lists the names that may stay in both languages, one per line:
# `name  kind  reason`, kind being
#   wrapper    the C++ side (and the shader's, when it is not the shared file itself) only calls the
#              same shared function (the GLSL one passes its uniform block, the C++ one its members);
#   reference  the C++ side is a deliberately different computation (an independent double
#              precision reference the tests compare the shader with);
#   unrelated  only the name is shared (different functions);
#   pending    still a hand-mirrored copy (the work left of issue 24 item 3);
#   standard   (a literal) a constant of nature or of a standard (pi) written where it is used.
#
# A copy under another name (or none: a few lines inside a pass's main()) escapes the names, so the
# shaders that are not shared files are also compared with the library's C++ by
#   literals     a decimal literal (outside comments) of at least 5 significant digits written in
#                both (the Gaussian FWHM factor 2.35482 of the Stars' and Planet's shaders and
#                planet.cpp was one);
#   expressions  the right-hand side of an assignment or a `return` with at least 6 operations
#                (binary + - * /, calls) of the same shape in both: variables folded to `v`,
#                `std::`/`glm::` and the float()/double() casts dropped, `1.0f` read as `1.0`, the
#                called functions kept by name (the sky-view texel's `clamp(sinV * sinS * cos(az)
#                + mu * muS, -1.0, 1.0)` in skyview_lut.glsl and sky_model.cpp was one).
# Their keys are the literal and the shape themselves (no spaces), listed like names.
# Output: one line per key found in both, `key  [kind]  glsl-files  |  cpp-files`; after each of
# the three the counts; last `in all: new N, pending N`. --check fails on a key the lists do not
# know (a new copy: move it to a shared file, or list it with its reason) and on a listed key no
# longer found in both (keep the list true).
#
# --constants (informational, exit 0): a copy named differently on each side (the sky-shadow march
# of cloud_sky_shadow.glsl and cpu::skyShadowLoss(), say) escapes the name check, but a hand copy
# usually repeats its fitted coefficients. Lists every decimal literal (outside // comments) with at
# least 4 significant digits written both in a shader and in the library's C++ (`literal
# glsl-files  |  cpp-files`):
# physical constants (luminous efficacy, Rec. 709 luminance weights) are expected there; a fit's
# coefficient or a model's constant points at a twin to move into a shared file.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
check=""
constants=""
if [ "${1:-}" = "--check" ]; then check=1; shift; elif [ "${1:-}" = "--constants" ]; then constants=1; shift; fi
if [ $# -gt 0 ]; then echo "twins-check.sh: the options are --check and --constants" >&2; exit 2; fi
allowed="$here/scripts/twins-allowed.txt"
cd "$here"

if [ -n "$constants" ]; then
  tmpc=$(mktemp -d)
  trap 'rm -rf "$tmpc"' EXIT
  # `literal<TAB>file` for each decimal literal outside // comments (a header's prose may cite a fit)
  literals='s{//.*}{}; while (/(?<![\w.])(\d+\.\d+(?:e[-+]?\d+)?)/g) { print "$1\t$ARGV\n" }'
  # significant digits: the mantissa's digits without leading zeros
  sig() { awk -F'\t' '{m=$1; sub(/[eE].*/, "", m); gsub(/\./, "", m); sub(/^0+/, "", m); sub(/0+$/, "", m); if (length(m) >= 4) print}'; }
  find engine generators skyelements -name '*.glsl' -print0 | sort -z | xargs -0 perl -ne "$literals" | sig | sort -u > "$tmpc/glsl"
  find engine generators skyelements apps examples \( -name '*.cpp' -o -name '*.hpp' \) ! -path '*/tests/*' ! -path '*/bench/*' -print0 |
    sort -z | xargs -0 perl -ne "$literals" | sig | sort -u > "$tmpc/cpp"
  join -t$'\t' -o 0 <(cut -f1 "$tmpc/glsl" | sort -u) <(cut -f1 "$tmpc/cpp" | sort -u) > "$tmpc/both"
  while read -r v; do
    g=$(awk -F'\t' -v k="$v" '$1 == k {print $2}' "$tmpc/glsl" | sort -u | paste -sd' ' -)
    c=$(awk -F'\t' -v k="$v" '$1 == k {print $2}' "$tmpc/cpp" | sort -u | paste -sd' ' -)
    printf '%-18s %s  |  %s\n' "$v" "$g" "$c"
  done < "$tmpc/both"
  echo "literals with >= 4 significant digits in both a shader and C++: $(wc -l < "$tmpc/both")"
  exit 0
fi

# key = lower-case name without a family prefix
normalise() { sed -E 's/^(atm|cld|welkin|pp|planet|rainbow|night|stars|lighting|clouds)_//' | tr 'A-Z' 'a-z'; }

# GLSL: top-level `TYPE NAME(` lines of every shader, the shared ones included.
glsl_defs() {
  find engine generators skyelements -name '*.glsl' -print0 | sort -z |
    xargs -0 grep -HoP '^(?:(?:highp|mediump|lowp|precise)\s+)?[A-Za-z_]\w*(?:\[\w+\])?\s+\K[A-Za-z_]\w*(?=\s*\()' |
    grep -v ':main$' || true
}
# C++: `TYPE NAME(` where TYPE is a type (qualified, templated, pointer or reference), in the
# library's and apps' sources (tests and benches compare twins, they do not hold them).
cpp_defs() {
  find engine generators skyelements apps examples \( -name '*.cpp' -o -name '*.hpp' \) \
      ! -path '*/tests/*' ! -path '*/bench/*' -print0 | sort -z |
    xargs -0 grep -HoP '^\s*(?:(?:static|inline|constexpr|virtual|explicit|friend|extern|\[\[nodiscard\]\])\s+)*(?!(?:return|else|if|while|for|switch|case|new|delete|throw|using|typedef|goto|co_return|sizeof|do|not|and|or)\b)[A-Za-z_][\w:]*(?:<[^;()]*>)?(?:\s*[*&]+\s*|\s+)(?:[A-Za-z_]\w*::)*\K[A-Za-z_]\w*(?=\s*\((?!.*\)\s*[,;]\s*$))' |
    grep -v ':main$' | grep -vE ':(operator|TEST_CASE|SECTION)$' || true
}

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
glsl_defs | awk -F: '{print $NF"\t"$1}' > "$tmp/glsl.raw"
cpp_defs | awk -F: '{print $NF"\t"$1}' > "$tmp/cpp.raw"
for side in glsl cpp; do
  paste <(cut -f1 "$tmp/$side.raw" | normalise) "$tmp/$side.raw" | sort -u > "$tmp/$side"
done
join -t$'\t' -o 0 <(cut -f1 "$tmp/glsl" | sort -u) <(cut -f1 "$tmp/cpp" | sort -u) > "$tmp/both"

# Copies the names cannot see (another name each side, or no function of their own): the shaders
# that are not shared files against the library's C++ (a shared file's text is one source already).
#  - literals: a decimal literal (outside comments) of at least 5 significant digits written in both
#    (a fit's coefficient, a model's constant: the Gaussian FWHM factor 2.35482 was one);
#  - expressions: the right-hand side of an assignment or a `return` with at least 6 operations
#    (binary + - * /, calls) written in both with the same shape: names of variables folded to `v`,
#    `std::`/`glm::` and the casts float()/double() dropped, `1.0f` read as `1.0`, calls kept by name
#    (the sky-view texel's `clamp(sinV * sinS * cos(az) + mu * muS, -1.0, 1.0)` was one).
# Keys are the literal and the shape themselves; scripts/twins-allowed.txt lists the ones that may
# stay, with the kinds above (a copy that is neither a standard's constant nor a deliberately
# independent reference is `pending`) or `standard` (a constant of nature or of a standard, such as
# pi, written where it is used).
own_glsl() { find engine generators skyelements -name '*.glsl' ! -name '*.shared.glsl' -print0 | sort -z; }
lib_cpp() { find engine generators skyelements apps examples \( -name '*.cpp' -o -name '*.hpp' \) ! -path '*/tests/*' ! -path '*/bench/*' -print0 | sort -z; }
literals='s{/\*.*?\*/}{}g; s{//.*}{}; while (/(?<![\w.])(\d+\.\d+(?:e[-+]?\d+)?)/g) { my $v = $1; (my $m = $v) =~ s/[eE].*//; $m =~ s/\.//; $m =~ s/^0+//; $m =~ s/0+$//; print "$v\t$ARGV\n" if length($m) >= 5 }'
shapes='
  BEGIN { $/ = undef }
  my $t = $_;
  $t =~ s{/\*.*?\*/}{ }gs; $t =~ s{//[^\n]*}{}g; $t =~ s{^\s*#[^\n]*}{}gm;
  for my $st (split /[;{}]/, $t) {
    my $rhs;
    if ($st =~ /\breturn\b(.*)$/s) { $rhs = $1 } elsif ($st =~ /^[^=]*?[^=!<>+\-*\/]=(?!=)(.*)$/s) { $rhs = $1 } else { next }
    $rhs =~ s/\b(?:std|glm)::/ /g; $rhs =~ s/\s+//g;
    $rhs =~ s/\b(\d+\.\d*|\.\d+)f\b/$1/g;
    $rhs =~ s/\b(?:float|double|real)\(/real(/g;
    my $calls = () = $rhs =~ /\b[A-Za-z_]\w*\(/g;
    my $ops = () = $rhs =~ /(?<=[\w.)\]])[-+*\/](?=[\w.(])/g;
    next if $calls + $ops < 6;
    (my $shape = $rhs) =~ s/\b(?!\d)[A-Za-z_]\w*(?:\.[A-Za-z_]\w*)*\b(?!\()/v/g;
    $shape =~ s/\breal\(v\)/v/g;
    print "$shape\t$ARGV\n";
  }'
own_glsl | xargs -0 -r perl -ne "$literals" | sort -u > "$tmp/lit.glsl"
lib_cpp | xargs -0 -r perl -ne "$literals" | sort -u > "$tmp/lit.cpp"
own_glsl | xargs -0 -r -n1 perl -ne "$shapes" | sort -u > "$tmp/expr.glsl"
lib_cpp | xargs -0 -r -n1 perl -ne "$shapes" | sort -u > "$tmp/expr.cpp"
for cat in lit expr; do
  for side in glsl cpp; do
    paste <(cut -f1 "$tmp/$cat.$side" | normalise) "$tmp/$cat.$side" | sort -u > "$tmp/$cat.$side.k"
  done
  join -t$'\t' -o 0 <(cut -f1 "$tmp/$cat.glsl.k" | sort -u) <(cut -f1 "$tmp/$cat.cpp.k" | sort -u) > "$tmp/$cat.both"
done

# The list: scripts/twins-allowed.txt for the engine's and generators' names, and an element
# folder's own skyelements/<name>/twins-allowed.txt for its names (so that they go with the
# folder: a tree without the element has neither the functions nor their entries).
declare -A kind
for list in "$allowed" skyelements/*/twins-allowed.txt; do
  [ -f "$list" ] || continue
  while read -r name k _; do
    case "$name" in ''|'#'*) continue ;; esac
    case "$k" in wrapper|reference|unrelated|pending|standard) ;; *) echo "twins-check.sh: $list: '$name' has kind '$k' (wrapper, reference, unrelated, standard or pending)" >&2; exit 2 ;; esac
    kind[$(printf '%s' "$name" | normalise)]=$k
  done < "$list"
done

declare -A seen
newTotal=0
pendingTotal=0
# report CATEGORY-FILE-PREFIX LABEL: one line per key found in both, then the category's counts
report() {
  local both=$1 g=$2 c=$3 label=$4
  local -A count=([wrapper]=0 [reference]=0 [unrelated]=0 [standard]=0 [pending]=0 [new]=0)
  local key k gf cf
  while IFS= read -r key; do
    k=${kind[$key]:-new}
    seen[$key]=1
    count[$k]=$((count[$k] + 1))
    gf=$(awk -F'\t' -v k="$key" '$1 == k {print $3}' "$g" | sort -u | paste -sd' ' -)
    cf=$(awk -F'\t' -v k="$key" '$1 == k {print $3}' "$c" | sort -u | paste -sd' ' -)
    printf '%-28s [%s]  %s  |  %s\n' "$key" "$k" "$gf" "$cf"
  done < "$both"
  echo "$label: $(wc -l < "$both") (wrapper ${count[wrapper]}, reference ${count[reference]}, unrelated ${count[unrelated]}, standard ${count[standard]}, pending ${count[pending]}, new ${count[new]})"
  newTotal=$((newTotal + count[new]))
  pendingTotal=$((pendingTotal + count[pending]))
}
report "$tmp/both" "$tmp/glsl" "$tmp/cpp" "duplicated names"
report "$tmp/lit.both" "$tmp/lit.glsl.k" "$tmp/lit.cpp.k" "literals of >= 5 digits in a shader and C++"
report "$tmp/expr.both" "$tmp/expr.glsl.k" "$tmp/expr.cpp.k" "expressions of one shape in a shader and C++"
stale=0
for key in "${!kind[@]}"; do
  if [ -z "${seen[$key]:-}" ]; then
    echo "twins-check.sh: '$key' is in scripts/twins-allowed.txt but no longer defined in both languages: remove it from the list" >&2
    stale=$((stale + 1))
  fi
done
echo "in all: new $newTotal, pending $pendingTotal"
if [ -n "$check" ]; then
  if [ "$newTotal" -gt 0 ]; then
    echo "twins-check.sh: $newTotal function(s), literal(s) or expression(s) written both in a shader and C++ ([new] above): write it once in a *.shared.glsl file (docs/architecture.md, \"One source\") or list it in scripts/twins-allowed.txt with its reason" >&2
  fi
  [ "$newTotal" -eq 0 ] && [ "$stale" -eq 0 ] || exit 1
fi
