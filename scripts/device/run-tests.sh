#!/usr/bin/env bash
# Second device run: the [gl] failures in full and the [slow] tests.
set -u
. .gpu/env.sh
mkdir -p /tmp/r && cd /tmp/r
t0=$(date +%s)
timeout 150 /work/main/build/tests/welkin_tests "[gl]~[slow]" -r compact 2>&1 | grep -v "performance warning" > $OUT/gl.txt
echo "gl: $(( $(date +%s) - t0 )) s" >> $OUT/gl.txt
t0=$(date +%s)
timeout 150 /work/main/build/tests/welkin_tests "[slow]" -r compact 2>&1 | grep -v "performance warning" > $OUT/slow.txt
echo "slow: $(( $(date +%s) - t0 )) s" >> $OUT/slow.txt
W=/work/main/build/bin/welkin
for i in 1 2; do /usr/bin/time -f "render %e s" $W render --time 2026-06-21T19:30:00+02:00 --lat 35.9 --lon 14.5 --az 290 --alt 10 --fov 70 --size 1280x720 --out $OUT/gpu-default.png --stats $OUT/stats.json 2>&1 | tail -3; done
tail -n 3 $OUT/gl.txt $OUT/slow.txt
