#!/usr/bin/env bash
# Device run: welkin bench all --quick (the harness's table with absolute times on the GPU).
set -u
root=$(pwd)
for f in .gl/*.deb; do dpkg -x "$f" /; done; ldconfig
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export LD_LIBRARY_PATH=$root/.gpu/lib
mkdir -p /usr/share/kstars /usr/share/stellarium/textures /usr/share/fonts/truetype/dejavu
cp .gpu/data/kstars/* /usr/share/kstars/; cp .gpu/data/stellarium/* /usr/share/stellarium/textures/
cp .gpu/data/fonts/* /usr/share/fonts/truetype/dejavu/
mkdir -p $OUT/plots
timeout 105 .gpu/bin/welkin bench all --quick --framework-frames 0 --out $OUT/BENCHMARKS-H100.md --plots $OUT/plots 2>&1 | tail -n 15
