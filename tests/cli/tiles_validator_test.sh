#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# CesiumGS's 3D Tiles validator on tilesets lasmesh writes, plain and Draco: no errors. Skipped
# (77) where the npm registry did not have the validator for tools/test.sh to install.
# Usage: tiles_validator_test.sh LASMESH LASGEN VALIDATOR_FOLDER
set -u
lasmesh=$1 lasgen=$2 validator=$3/node_modules/.bin/3d-tiles-validator here=$(dirname "$0")
if [ ! -x "$validator" ]; then
  echo "tiles_validator: skipped: no 3d-tiles-validator at $validator"
  exit 77
fi
source "$here/common.sh"

"$lasgen" --scene deck --points 300000 --epsg 32631 -o "$dir/deck.las" > /dev/null
"$lasgen" --scene deck --points 100000 -o "$dir/local.las" > /dev/null
mkdir -p "$dir/plain" "$dir/draco" "$dir/local"
"$lasmesh" "$dir/deck.las" -o "$dir/plain/tileset.json" -q
"$lasmesh" "$dir/deck.las" -o "$dir/draco/tileset.json" --glb-compression draco -q
"$lasmesh" "$dir/local.las" -o "$dir/local/tileset.json" -q
for kind in plain draco local; do
  "$validator" --tilesetFile "$dir/$kind/tileset.json" --reportFile "$dir/$kind.report.json" > "$dir/$kind.out" 2>&1
  check "$kind tileset: the validator ran" test -s "$dir/$kind.report.json"
  check "$kind tileset: no errors" python3 -c '
import json, sys
report = json.load(open(sys.argv[1]))
for issue in report.get("issues", [])[:5]: print(issue)
assert report["numErrors"] == 0, report["numErrors"]' "$dir/$kind.report.json"
done

finish tiles_validator
