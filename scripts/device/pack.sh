#!/usr/bin/env bash
# Packs what a GPU machine without Debian's packages needs to run welkin's tests and benches:
#   scripts/device/pack.sh BUILD_DIR     (BUILD_DIR configured with -DWELKIN_IMAGE_IO=builtin)
# writes .gpu/ (binaries, their shared libraries but libc/libGL/libEGL, the kstars and Stellarium
# data the tests read, the font) and .gl/ (glvnd's libEGL/libGL .debs, unpacked there), both
# ignored by git. Then run scripts/device/run-benches.sh or run-tests.sh there, carrying .gl and
# .gpu (docs/gpu.md). OpenImageIO's ~260 libraries do not fit a 64 MiB carry: hence builtin.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${1:?usage: scripts/device/pack.sh BUILD_DIR}
cd "$here"
grep -q '^WELKIN_IMAGE_IO:STRING=builtin' "$build/CMakeCache.txt" || { echo "pack.sh: $build is not a WELKIN_IMAGE_IO=builtin build" >&2; exit 2; }
grep -qx '/.gpu/' .git/info/exclude 2>/dev/null || printf '/.gl/\n/.gpu/\n' >> .git/info/exclude
rm -rf .gpu && mkdir -p .gpu/bin .gpu/lib .gpu/data/kstars .gpu/data/stellarium .gpu/data/fonts
cp "$build/bin/welkin" "$build/tests/welkin_tests" .gpu/bin/
ldd .gpu/bin/welkin .gpu/bin/welkin_tests | awk '/=>/{print $3}' | sort -u |
  grep -v -E "/(libc|libm|libdl|libpthread|librt|ld-linux-x86-64|libEGL|libGL|libGLX|libGLdispatch|libOpenGL|libgcc_s)\.so" |
  xargs -r cp -L -t .gpu/lib/
cp /usr/share/kstars/*.vsop .gpu/data/kstars/
for f in stars.dat namedstars.dat unnamedstars.dat clines.dat cnames.dat moonB.dat moonLR.dat; do cp "/usr/share/kstars/$f" .gpu/data/kstars/; done
cp /usr/share/stellarium/textures/{milkyway.png,moon_4k.jpg,moon_normals.png} .gpu/data/stellarium/
cp /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf .gpu/data/fonts/
cp scripts/device/run-*.sh scripts/device/env.sh .gpu/
if [ ! -d .gl ]; then
  mkdir -p .gl /tmp/amd64/partial
  o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
  apt-get $o update >/dev/null
  (cd .gl && apt-get $o download libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2 >/dev/null)
fi
du -sh .gpu .gl
