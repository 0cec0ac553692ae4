#!/usr/bin/env bash
# The images of this element's page (README.md) that scripts/doc-images.sh re-renders: run from the
# repository root with the welkin command as the argument (scripts/doc-images.sh does both; see
# docs/writing-an-element.md, "The folder"). Deleting the folder deletes its images' commands too.
set -euo pipefail
w=${1:?usage: skyelements/constellations/doc-images.sh PATH/TO/welkin}
"$w" render --time 2026-08-12T22:00:00Z --lat 35.9 --lon 14.5 --projection fisheye --size 1024x1024 --elements stars,sky,constellations --exposure -9 --out skyelements/constellations/images/constellations_malta.png
