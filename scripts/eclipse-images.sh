#!/usr/bin/env bash
# Renders docs/eclipse.md's three total eclipses at second contact, mid-totality and third contact:
# 2026-08-12 from Burgos and from Reykjavik, 2027-08-02 from Luxor; for each place and instant a
# fisheye of the whole sky and a 2.0 deg view centred on the Sun, default elements, automatic
# exposure, 256 x 256. The instants come from `welkin astro --events` at each place:
#   c2  = 4 s before second contact, the earlier of the smooth limb's (c2) and the limb profile's
#         (c2_limb): the last beads, and the diamond ring's glare (drawn while the smooth limb's
#         visible fraction is between 0 and 1 %)
#   mid = the maximum (least separation)
#   c3  = 4 s after third contact, the later of c3 and c3_limb: the first beads and the diamond ring
# and the Sun's direction for the Sun views from `welkin astro --json` at that instant (apparent,
# refracted altitude). Writes docs/images/eclipse_<place>_{fisheye,sun}_<c2|mid|c3>.png (the
# mid-totality fisheye is the page's eclipse_<place>_fisheye.png again, rendered by this script with
# the maximum that the events give now; the older images are left alone).
# Every render command is printed as it runs. ~25 s a place on llvmpipe (1 min 16 s in all,
# 2026-11-27, 2 cores, load 7.8; 2 min 13 s on 2026-11-28 00:32 UTC, load ~9).
# Usage: scripts/eclipse-images.sh [BUILD_DIR]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$here/build}
w="$build/bin/welkin"
cd "$here"

offset_s=4     # seconds before C2 / after C3
size=256x256
sun_fov=2.0    # degrees: the Sun (0.53 deg) and the corona out to 3.8 solar radii at the sides, 5.4
               # at the corners (the corona is drawn out to 30 R_sun since 2026-11-28)

# place name, latitude, longitude, start of the day searched (UTC)
places=(
  "burgos 42.34 -3.70 2026-08-12"
  "reykjavik 64.15 -21.94 2026-08-12"
  "luxor 25.69 32.64 2027-08-02"
)

run() { echo "welkin ${*:2}"; "$@" >/dev/null; }

for p in "${places[@]}"; do
  read -r name lat lon day <<<"$p"
  next=$(date -u -d "$day + 1 day" +%F)
  # c2, mid, c3 instants (ISO 8601, UTC) from the local circumstances
  read -r t_c2 t_mid t_c3 < <("$w" astro --time "${day}T00:00:00Z" --lat "$lat" --lon "$lon" --events \
      --to "${next}T00:00:00Z" --json | python3 -c '
import json, sys, datetime as dt
off = dt.timedelta(seconds=int(sys.argv[1]))
e = [s for s in json.load(sys.stdin)["eclipses"]["solar"] if s["type"] == "total"]
if len(e) != 1: sys.exit("expected one total solar eclipse that day, found %d" % len(e))
e = e[0]
def t(k): return dt.datetime.strptime(e[k]["time"], "%Y-%m-%dT%H:%M:%SZ")
f = lambda x: x.strftime("%Y-%m-%dT%H:%M:%SZ")
print(f(min(t("c2"), t("c2_limb")) - off), f(t("maximum")), f(max(t("c3"), t("c3_limb")) + off))
sys.stderr.write("C2 %s (limb; smooth %s), maximum %s, C3 %s (limb; smooth %s)\n" % (
    e["c2_limb"]["time"], e["c2"]["time"], e["maximum"]["time"], e["c3_limb"]["time"], e["c3"]["time"]))
' "$offset_s")
  echo "== $name: c2 $t_c2, mid $t_mid, c3 $t_c3"
  for phase in c2 mid c3; do
    case $phase in c2) t=$t_c2 ;; mid) t=$t_mid ;; c3) t=$t_c3 ;; esac
    fish=docs/images/eclipse_${name}_fisheye_${phase}.png
    run "$w" render --time "$t" --lat "$lat" --lon "$lon" --elements default --projection fisheye \
      --size "$size" --out "$fish"
    read -r az alt < <("$w" astro --time "$t" --lat "$lat" --lon "$lon" --json | python3 -c '
import json, sys; s = json.load(sys.stdin)["bodies"]["sun"]; print("%.3f %.3f" % (s["az_deg"], s["alt_deg"]))')
    run "$w" render --time "$t" --lat "$lat" --lon "$lon" --elements default --az "$az" --alt "$alt" \
      --fov "$sun_fov" --size "$size" --out "docs/images/eclipse_${name}_sun_${phase}.png"
  done
done
echo "== done"
