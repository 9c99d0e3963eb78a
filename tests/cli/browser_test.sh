#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Tilesets in real viewers: CesiumJS and three.js with 3DTilesRendererJS, in headless Chromium
# (tests/browser/viewers.js), plain and Draco tiles. Each viewer loads the tileset without an
# error, draws it, asks for the root first and for every tile's parent, and reaches the finest
# level; CesiumJS puts the root where the transform says, and near the data's centre.
# LASMESH_SCREENSHOTS=FOLDER keeps a picture per viewer (docs/img/tileset_*.png come from here).
# Skipped (77) where Chromium or the browser packages are not installed (tools/test.sh installs
# them).
# Usage: browser_test.sh LASMESH LASGEN BROWSER_PACKAGES_FOLDER
set -u
lasmesh=$1 lasgen=$2 packages=$3 here=$(dirname "$0")
source "$here/common.sh"
viewers=$here/../browser/viewers.js

"$lasgen" --scene deck --points 300000 --epsg 32631 -o "$dir/deck.las" > /dev/null
mkdir -p "$dir/plain" "$dir/draco"
"$lasmesh" "$dir/deck.las" -o "$dir/plain/tileset.json" -q
"$lasmesh" "$dir/deck.las" -o "$dir/draco/tileset.json" --glb-compression draco -q



shots=()
[ -n "${LASMESH_SCREENSHOTS:-}" ] && shots=(--screenshots "$LASMESH_SCREENSHOTS")
node "$viewers" "$packages" "$dir/plain/tileset.json" --sse 1 "${shots[@]}" > "$dir/plain.txt"; rc=$?
cat "$dir/plain.txt"
[ "$rc" -eq 77 ] && exit 77
check "plain tiles: every viewer check passes" test "$rc" -eq 0
node "$viewers" "$packages" "$dir/draco/tileset.json" --sse 1 > "$dir/draco.txt"; rc=$?
cat "$dir/draco.txt"
check "Draco tiles: every viewer check passes" test "$rc" -eq 0
check "both viewers ran" test "$(grep -c "^ok - .*: draws it" "$dir/plain.txt")" -eq 2

finish browser
