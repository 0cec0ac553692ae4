#!/usr/bin/env bash
# Second device run: the [gl] failures in full and the [slow] tests.
set -u
root=$(pwd)
for f in .gl/*.deb; do dpkg -x "$f" /; done; ldconfig
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export LD_LIBRARY_PATH=$root/.gpu/lib
mkdir -p /usr/share/kstars /usr/share/stellarium/textures /usr/share/fonts/truetype/dejavu /work
cp .gpu/data/kstars/* /usr/share/kstars/; cp .gpu/data/stellarium/* /usr/share/stellarium/textures/
cp .gpu/data/fonts/* /usr/share/fonts/truetype/dejavu/
[ "$root" = /work/main ] || ln -sfn "$root" /work/main
mkdir -p build/bin build/tests
cp .gpu/bin/welkin build/bin/; cp .gpu/bin/welkin_tests build/tests/
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
