#!/usr/bin/env bash
# Device run: the 10,000-frame soak with every element, then the [gl] tests of the same build.
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
W=/work/main/build/bin/welkin
t0=$(date +%s)
timeout 300 $W bench soak --rows 10 > $OUT/soak.txt 2>&1; echo "soak rc=$? in $(( $(date +%s) - t0 )) s" >> $OUT/soak.txt
t0=$(date +%s)
timeout 80 /work/main/build/tests/welkin_tests "[gl]~[slow]" -r compact 2>&1 | grep -v "^welkin warning" > $OUT/gl.txt
echo "gl: $(( $(date +%s) - t0 )) s" >> $OUT/gl.txt
tail -n 25 $OUT/soak.txt; tail -n 12 $OUT/gl.txt
