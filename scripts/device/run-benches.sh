#!/usr/bin/env bash
# One prepared device run: [gl] tests and the benches on the GPU; everything lands in $OUT.
set -u
log=$OUT/log.txt
exec > >(tee -a "$log") 2>&1
t0=$(date +%s)
stamp() { echo "== [$(( $(date +%s) - t0 )) s] $*"; }
. .gpu/env.sh  # glvnd, the carried libraries, data and binaries (scripts/device/env.sh)
nvidia-smi -L; nvidia-smi --query-gpu=name,driver_version,clocks.sm --format=csv
stamp "render check"
$W render --time 2026-06-21T19:30:00+02:00 --lat 35.9 --lon 14.5 --az 290 --alt 10 --fov 70 --size 1280x720 --out $OUT/gpu-default.png --stats 2>&1 | head -40
mkdir -p /tmp/r && cd /tmp/r
stamp "gl tests"
timeout 180 /work/main/build/tests/welkin_tests "[gl]~[slow]" -r compact 2>&1 | tail -60
stamp "bench frame 1280x720"; timeout 40 $W bench frame --size 1280x720 --repeats 20
stamp "bench frame 1920x1080"; timeout 40 $W bench frame --size 1920x1080 --repeats 20
stamp "bench night"; timeout 60 $W bench night --repeats 20 --csv /tmp/r/night.csv
stamp "bench sky"; timeout 60 $W bench sky --timing-only --repeats 20 --csv /tmp/r/sky.csv
stamp "bench clouds"; timeout 60 $W bench clouds --sizes 1280x720,1920x1080 --repeats 5 --moving-frames 60 --csv /tmp/r/clouds.csv --plot ""
stamp "bench rainbow"; timeout 40 $W bench rainbow --repeats 20 --csv /tmp/r/rainbow.csv
stamp "bench lighting"; timeout 40 $W bench lighting --csv /tmp/r/lighting.csv
stamp "done"
tar czf $OUT/csv.tgz -C /tmp/r --exclude='*.png' . 2>/dev/null
