#!/usr/bin/env bash
# The images of this element's page (README.md) that scripts/doc-images.sh re-renders: run from the
# repository root with the welkin command as the argument (scripts/doc-images.sh does both; see
# docs/writing-an-element.md, "The folder"). Deleting the folder deletes its images' commands too.
set -euo pipefail
w=${1:?usage: skyelements/clouds/doc-images.sh PATH/TO/welkin}
"$w" render --time 2026-06-29T23:30:00+02:00 --lat 35.9 --lon 14.5 --az 150 --alt 20 --fov 75 --size 480x270 --elements default,clouds --var clouds.preset=fair --out skyelements/clouds/images/clouds_moonlit.png
# The data images: weather map, noise slices, density section.
"$w" bench cloud-doc-images --out skyelements/clouds/images >/dev/null
