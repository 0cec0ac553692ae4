# Sourced by the run-*.sh scripts on the GPU machine, from the repository root: unpacks glvnd
# (.gl), points the loader at the carried libraries, installs the carried data where welkin reads
# it, and puts the binaries where the tests' compiled-in paths (/work/main/build) expect them.
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
W=/work/main/build/bin/welkin
