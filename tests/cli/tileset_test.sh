#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# `-o site/tileset.json`: a 3D Tiles tileset whose every tile passes the Khronos glTF validator,
# plain and Draco-compressed, placed on the globe with a CRS and said not to be without one; a
# missing folder fails before reading, and nothing is left behind.
# Usage: tileset_test.sh LASMESH LASGEN VALIDATOR_FOLDER
set -u
lasmesh=$1 lasgen=$2 validator=$3 here=$(dirname "$0")
source "$here/common.sh"

"$lasgen" --scene deck --points 300000 --epsg 32631 -o "$dir/deck.las" > /dev/null
mkdir -p "$dir/site" "$dir/draco"
"$lasmesh" "$dir/deck.las" -o "$dir/site/tileset.json" > "$dir/summary.txt" 2>&1
check "a tileset is written" test -s "$dir/site/tileset.json"
check "the summary names it" has "$dir/summary.txt" "site/tileset.json"
check "placed: no note" lacks "$dir/summary.txt" "not placed on the globe"
# tiles_of JSON: every content the tileset names, one path a line, checked to exist.
tiles_of() { python3 -c '
import json, os, sys
root = os.path.dirname(sys.argv[1])
def walk(n):
    if "content" in n: yield os.path.join(root, n["content"]["uri"])
    for c in n.get("children", []): yield from walk(c)
t = json.load(open(sys.argv[1]))
assert t["asset"]["version"] == "1.1" and len(t["root"]["transform"]) == 16
for p in walk(t["root"]):
    assert os.path.isfile(p), p
    print(p)' "$1"; }
tiles_of "$dir/site/tileset.json" > "$dir/tiles.txt"
check "every tile the tileset names exists" test "$(wc -l < "$dir/tiles.txt")" -gt 4
check "no temporary folder left" test -z "$(find "$dir/site" -name '.lasmesh-*')"
mapfile -t tiles < "$dir/tiles.txt"
node "$here/gltf_validate.js" "$validator" "${tiles[@]}" > "$dir/validator.txt"; rc=$?
check "glTF validator: no errors in any tile" test "$rc" -eq 0
grep -v ": 0 errors" "$dir/validator.txt" | head -5

# info: the levels, and the finest level's triangles counted from the tiles are the run's mesh's.
"$lasmesh" info "$dir/site/tileset.json" > "$dir/info.txt"
check "info names the tileset and its placement" has "$dir/info.txt" "placed               on the globe"
"$lasmesh" info --json "$dir/site/tileset.json" > "$dir/info.json"
mesh_triangles=$(awk '$1 == "mesh" {print $4}' "$dir/summary.txt")
check "info: the finest level's triangles are the mesh's" python3 -c '
import json, sys
info = json.load(open(sys.argv[1]))
t = json.load(open(sys.argv[2]))
assert len(info["levels"]) == len(t["extras"]["lasmesh"]["levels"]) >= 2, info
assert info["levels"][-1]["triangles"] == int(sys.argv[3]), (info["levels"][-1], sys.argv[3])
assert info["levels"][0]["tiles"] == 1 and info["placed"] is True' "$dir/info.json" "$dir/site/tileset.json" "$mesh_triangles"
echo '{"asset": {}}' > "$dir/bad.json"
"$lasmesh" info "$dir/bad.json" > "$dir/bad.txt" 2>&1; rc=$?
check "info of a JSON that is no tileset: input error naming it" test "$rc" -eq 2
check "and saying why" has "$dir/bad.txt" "bad.json: not a 3D Tiles tileset"

"$lasmesh" "$dir/deck.las" -o "$dir/draco/tileset.json" --glb-compression draco -q
tiles_of "$dir/draco/tileset.json" > "$dir/draco.txt"
mapfile -t tiles < "$dir/draco.txt"
node "$here/gltf_validate.js" "$validator" "${tiles[@]}" > "$dir/validator.txt"; rc=$?
check "Draco tiles: no validator errors" test "$rc" -eq 0
check "Draco tiles use KHR_draco_mesh_compression" grep -q "KHR_draco_mesh_compression" "${tiles[0]}"
check "Draco tiles are smaller" test "$(cat "${tiles[@]}" | wc -c)" -lt \
  "$(xargs cat < "$dir/tiles.txt" | wc -c)"

"$lasgen" --scene deck --points 100000 -o "$dir/plain.las" > /dev/null
"$lasmesh" "$dir/plain.las" -o "$dir/plain.json" > "$dir/plain.txt" 2>&1
check "without a CRS: said not to be placed" has "$dir/plain.txt" "not placed on the globe: the input declares no coordinate system"

"$lasmesh" "$dir/deck.las" -o "$dir/missing/tileset.json" > "$dir/err.txt" 2>&1; rc=$?
check "a missing folder is an output error" test "$rc" -eq 4
check "and nothing was created" test ! -e "$dir/missing"
finish "cli tileset"
