#!/usr/bin/env bash
# Re-renders the README's gallery and the docs' images whose look depends on how point sources are
# displayed (render.point_sources: perceptual for PNG), with the commands printed beside them, then
# each element folder's own images: skyelements/<name>/doc-images.sh, where a folder has one (run
# from the repository root with the welkin command as its argument; the clouds' data images, the
# stars', night sky's and constellations' night views).
# Usage: scripts/doc-images.sh [BUILD_DIR]     (needs xvfb-run for the viewer's screenshot, oiiotool for the strips)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$here/build}
w="$build/bin/welkin"
img="$here/docs/images"
cd "$here"

echo "== heritage demo (README gallery, docs/demos.md)"
for site in kalabsha kiti; do
  "$w" demo heritage --site "$site" --date 2027-03-20 --size 480x270 --out docs/images --prefix demo-heritage- >/dev/null
done

echo "== education demo (README gallery, docs/demos.md): the demo's own images, renamed"
tmp=$(mktemp -d)
"$w" demo education --size 480x270 --out "$tmp" >/dev/null
for f in "$tmp"/*.png; do mv "$f" "$img/demo-education-$(basename "$f")"; done
rm -rf "$tmp"

echo "== time-lapse contact sheet (README gallery, docs/timelapse.md)"
tmp=$(mktemp -d)
"$w" timelapse --lat 35.9 --lon 14.5 --height 50 --az 295 --alt 8 --fov 70 --size 160x90 \
  --from 2026-06-21T17:30:00Z --to 2026-06-21T19:30:00Z --step 10m --out "$tmp/sunset" \
  --contact-sheet docs/images/timelapse-contact-sheet.png 2>/dev/null
rm -rf "$tmp"

echo "== the viewer with its panel (docs/viewer.md)"
xvfb-run -a -s '-screen 0 1024x768x24' "$w" view --lat 35.9 --lon 14.5 --height 50 \
  --time 2026-06-21T18:05:00Z --az 295 --alt 8 --fov 70 --size 640x360 --speed 1 \
  --frames 3 --screenshot docs/images/viewer-panel.png >/dev/null

echo "== night image (README)"
"$w" render --time 2026-08-12T22:00:00Z --lat 35.9 --lon 14.5 --projection fisheye --size 1024x1024 --out docs/images/malta_night_fisheye.png

echo "== the eye's day-to-night strips (docs/eye.md)"
tmp=$(mktemp -d)
times=(2026-08-12T17:30:00+02:00 2026-08-12T19:30:00+02:00 2026-08-12T20:10:00+02:00 2026-08-12T20:40:00+02:00 2026-08-27T23:30:00+02:00 2026-08-12T22:30:00+02:00)
for curve in aces hable; do
  frames=()
  for i in "${!times[@]}"; do
    "$w" render --time "${times[$i]}" --lat 35.9 --lon 14.5 --az 285 --alt 20 --fov 90 --size 192x144 \
      --var exposure.curve=$curve --out "$tmp/f$i.png" >/dev/null
    frames+=("$tmp/f$i.png")
  done
  out=docs/images/eye_strip_malta.png
  [ "$curve" = hable ] && out=docs/images/eye_strip_malta_hable.png
  oiiotool "${frames[@]}" --mosaic 6x1 -o "$out"
done
rm -rf "$tmp"

for f in skyelements/*/doc-images.sh; do
  [ -f "$f" ] || continue
  echo "== $(dirname "$f")/README.md's images ($f)"
  bash "$f" "$w"
done
echo "== done"
