#!/usr/bin/env bash
# Device run: the 10,000-frame soak with every element, then the [gl] tests of the same build.
set -u
. .gpu/env.sh
mkdir -p /tmp/r && cd /tmp/r
W=/work/main/build/bin/welkin
t0=$(date +%s)
timeout 300 $W bench soak --rows 10 > $OUT/soak.txt 2>&1; echo "soak rc=$? in $(( $(date +%s) - t0 )) s" >> $OUT/soak.txt
t0=$(date +%s)
timeout 80 /work/main/build/tests/welkin_tests "[gl]~[slow]" -r compact 2>&1 | grep -v "^welkin warning" > $OUT/gl.txt
echo "gl: $(( $(date +%s) - t0 )) s" >> $OUT/gl.txt
tail -n 25 $OUT/soak.txt; tail -n 12 $OUT/gl.txt
