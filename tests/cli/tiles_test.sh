#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# plan / tile / merge on this machine (tiles run by xargs -P): the merged outputs are byte for byte
# those of one run over the same inputs (a tileset, a PLY, a GLB), for the automatic grid and a
# cell edge, the grid held whole or (--in-tiles) the sheet meshed tile by tile from the tiles' files; a missing, damaged or foreign tile is named by merge, which writes nothing; a rerun
# tile replaces its file; a file whose header bounds lie (its points would be lost) stops its tile;
# an input changed since the plan is refused; the tile index comes from --index or the scheduler;
# a COPC file's tiles read only the octree nodes that touch them, cropped or not.
# Usage: tiles_test.sh LASMESH LASGEN
set -u
lasmesh=$1 lasgen=$2 here=$(dirname "$0")
source "$here/common.sh"
cd "$dir" || exit 1

"$lasgen" --scene deck --points 300000 --seed 5 --epsg 32631 --split-xy 3 -o deck.las > /dev/null
inputs=(deck-*.las)
mkdir -p one many again in-tiles thin-one thin-many ball-one ball-many
"$lasmesh" "${inputs[@]}" --tile 12 -o one/tileset.json -o one/mesh.ply -o one/mesh.glb > one.txt 2>&1
"$lasmesh" plan "${inputs[@]}" --tile 12 -o site.plan.json > plan.txt; rc=$?
check "plan: exit 0" test "$rc" -eq 0
tiles=$(python3 -c 'import json; print(len(json.load(open("site.plan.json"))["tiles"]))')
check "plan: several tiles" test "$tiles" -ge 4
check "plan: says how many tiles, and the array job's command" has plan.txt "$tiles tiles of 12"
check "plan: the sbatch line covers every tile" has plan.txt "sbatch --array=0-$((tiles - 1)) "
check "plan: every tile reads only some inputs" python3 -c '
import json; p = json.load(open("site.plan.json"))
assert all(0 < len(t["inputs"]) < len(p["inputs"]) for t in p["tiles"]), [t["inputs"] for t in p["tiles"]]'
# Each tile reads its inputs whole: the points read in all, against the survey's.
times=$(python3 -c '
import json; p = json.load(open("site.plan.json")); n = [i["points"] for i in p["inputs"]]
print("%.2g" % (sum(n[i] for t in p["tiles"] for i in t["inputs"]) / sum(n)))')
check "plan: says how many times the tile jobs read the inputs' points ($times)" \
  has plan.txt "the tile jobs read the inputs' points $times times in all"

seq 0 $((tiles - 1)) | xargs -P 2 -I K "$lasmesh" tile site.plan.json --index K -q; rc=$?
check "tiles: every one exit 0" test "$rc" -eq 0
check "tiles: one file each" test "$(ls site.plan-tiles | wc -l)" -eq "$tiles"
"$lasmesh" merge site.plan.json -o many/tileset.json -o many/mesh.ply -o many/mesh.glb -v > merge.txt 2>&1; rc=$?
check "merge: exit 0" test "$rc" -eq 0
check "merge: the summary names the outputs" has merge.txt "many/tileset.json"
check "merge: the grid held whole by default" bash -c "! grep -q 'the sheet meshed in ' merge.txt"
# --in-tiles: the sheet meshed tile by tile from the tiles' files, the grid never held whole.
"$lasmesh" merge site.plan.json --in-tiles -o in-tiles/tileset.json -o in-tiles/mesh.ply -o in-tiles/mesh.glb -v \
  > in-tiles.txt 2>&1; rc=$?
check "merge --in-tiles: exit 0" test "$rc" -eq 0
check "merge --in-tiles: the sheet meshed tile by tile" has in-tiles.txt "the sheet meshed in "
check "merge --in-tiles: one run's tileset, PLY and GLB, every file" diff -r one in-tiles
# The cells' counts from the tiles' files, as one run counts them in its grid (their median
# chooses the iso and says whether thin parts are refined).
summary() { grep -E '^(grid|iso|occupied|thin parts|pieces|simplify|mesh) ' "$1" | sed -E 's/ in [0-9.]+ s//g'; }
check "merge --in-tiles: the grid, the cells' counts and the mesh in the summary are one run's" \
  test "$(summary one.txt)" = "$(summary in-tiles.txt)"
"$lasmesh" merge site.plan.json --in-tiles -o in-tiles.ply > in-tiles-ply.txt 2>&1; rc=$?
check "merge --in-tiles without a tileset: usage error (1), says why" \
  bash -c "test $rc -eq 1 && grep -q 'give a tileset output' in-tiles-ply.txt && test ! -e in-tiles.ply"
check "merged PLY = one run's PLY, byte for byte" cmp -s one/mesh.ply many/mesh.ply
check "merged GLB = one run's GLB" cmp -s one/mesh.glb many/mesh.glb
check "merged tileset = one run's tileset, every file" diff -r one many
# The tileset's finest tiles are the plan's: one .glb for each planned tile with surface, named by
# its column and row, and their edge the plan's; without --tile (64 cells) one run's differ.
check "the finest tiles are the plan's tiles" python3 -c '
import json, os
p = json.load(open("site.plan.json")); t = json.load(open("many/tileset.json"))
levels = t["extras"]["lasmesh"]["levels"]
assert abs(levels[-1]["tile_size"] - p["tile"]["size"]) < 1e-9, (levels[-1], p["tile"])
folder = os.path.join("many", [d for d in os.listdir("many") if d.startswith("tileset-")][0], str(len(levels) - 1))
names = {n[:-4] for n in os.listdir(folder)}
planned = {"%d_%d" % (tile["x"], tile["y"]) for tile in p["tiles"]}
assert names and names <= planned and len(names) >= len(planned) - 1, (sorted(names), sorted(planned))'
printed=$(sed -n 's/.*lasmesh INPUTS\.\.\. --tile \([0-9.]*\) -o tileset.json.*/\1/p' plan.txt)
mkdir -p printed default
"$lasmesh" "${inputs[@]}" --tile "$printed" -o printed/tileset.json -q
check "the plan prints the --tile that gives its tileset on one machine" diff -r printed/tileset.json many/tileset.json
"$lasmesh" "${inputs[@]}" -o default/tileset.json -q
check "without --tile, one run's tileset has other tiles" bash -c "! diff -rq default/tileset.json many/tileset.json > /dev/null"
"$lasmesh" "${inputs[@]}" --tile 12 -o tile.ply > tile-ply.txt 2>&1; rc=$?
check "--tile without a tileset output: usage error (1) naming it" test "$rc" -eq 1 -a ! -e tile.ply
check "--tile without a tileset output: says why" has tile-ply.txt "--tile"
# Thin parts: the merge reads the inputs again for them, as one machine does.
"$lasmesh" "${inputs[@]}" -o thin-one.ply --refine-thin > thin-one.txt 2>&1
"$lasmesh" merge site.plan.json -o thin-many.ply --refine-thin > thin-many.txt 2>&1; rc=$?
check "merge --refine-thin: exit 0" test "$rc" -eq 0
check "merge --refine-thin: thin parts found and meshed" contains thin-many.txt "^thin parts     [1-9][0-9]* cells meshed"
thin_line() { grep '^thin parts ' "$1" | sed 's/, read again in .*//'; }
check "merge --refine-thin: the same thin parts as one run" test "$(thin_line thin-one.txt)" = "$(thin_line thin-many.txt)"
check "merge --refine-thin: PLY = one run's, byte for byte" cmp -s thin-one.ply thin-many.ply
# With a tileset, the sheet meshed tile by tile and the thin parts joined to it.
"$lasmesh" "${inputs[@]}" --tile 12 -o thin-one/tileset.json -o thin-one/mesh.ply --refine-thin -q
"$lasmesh" merge site.plan.json --in-tiles -o thin-many/tileset.json -o thin-many/mesh.ply --refine-thin -v \
  > thin-tiles.txt 2>&1
check "merge --refine-thin, a tileset: meshed tile by tile" has thin-tiles.txt "the sheet meshed in "
check "merge --refine-thin, a tileset: one run's, every file" diff -r thin-one thin-many
check "merge --refine-thin: the thin parts changed the mesh" bash -c "! cmp -s thin-many/mesh.ply one/mesh.ply"

# A cell edge instead of the automatic grid, tiles read one input at a time.
"$lasmesh" "${inputs[@]}" -o edge-one.ply --voxel 0.2 -q
"$lasmesh" plan "${inputs[@]}" --voxel 0.2 --tile 20 -o edge.json > /dev/null
for k in $(seq 0 $(($(python3 -c 'import json; print(len(json.load(open("edge.json"))["tiles"]))') - 1))); do
  "$lasmesh" tile edge.json --index "$k" --threads 1 -q
done
"$lasmesh" merge edge.json -o edge-many.ply -q
check "--voxel 0.2: merged PLY = one run's" cmp -s edge-one.ply edge-many.ply

# A noisy sphere: the automatic grid chosen from the headers is too fine, and one run coarsens it
# after counting (twice here); merge coarsens the merged grid the same way (whole, even when asked
# to mesh in tiles).
"$lasgen" --scene sphere --points 200000 --noise 0.3 --epsg 32631 --split-xy 2 -o ball.las > /dev/null
"$lasmesh" ball-*.las --tile 3 -o ball-one/tileset.json -o ball-one.ply > ball-one.txt 2>&1
check "the noisy sphere's grid is coarsened in one run" has ball-one.txt "times coarser"
"$lasmesh" plan ball-*.las --tile 3 -o ball.json > /dev/null
ball_tiles=$(python3 -c 'import json; print(len(json.load(open("ball.json"))["tiles"]))')
seq 0 $((ball_tiles - 1)) | xargs -P 2 -I K "$lasmesh" tile ball.json --index K -q
"$lasmesh" merge ball.json --in-tiles -o ball-many/tileset.json -o ball-many.ply -v > ball-many.txt 2>&1
check "merged: coarsened the same way (the summary's grid line)" test "$(grep '^grid ' ball-one.txt)" = "$(grep '^grid ' ball-many.txt)"
check "merged: the same PLY" cmp -s ball-one.ply ball-many.ply
check "merged: the same tileset" diff -r ball-one ball-many
check "merged --in-tiles: the grid coarsened, so meshed whole, with a note" bash -c \
  "! grep -q 'the sheet meshed in ' ball-many.txt && grep -q 'meshed whole, not in tiles' ball-many.txt"

# Missing, damaged, from another plan: all named at once, nothing written.
mv site.plan-tiles/tile-1.cells tile-1.saved
python3 -c '
import sys; f = open("site.plan-tiles/tile-2.cells", "r+b"); f.seek(200); b = f.read(1); f.seek(200); f.write(bytes([b[0] ^ 1]))'
cp edge-tiles/tile-3.cells site.plan-tiles/tile-3.cells # the same index, another plan
"$lasmesh" merge site.plan.json -o bad.ply > bad.txt 2>&1; rc=$?
check "merge with bad tiles: input error (2)" test "$rc" -eq 2
check "names the three tiles, as an array range" has bad.txt "3 of $tiles tiles missing or damaged: 1-3"
check "says tile 1 is missing" has bad.txt "tile-1.cells: missing"
check "says tile 2 is damaged" has bad.txt "tile-2.cells: damaged"
check "says tile 3 is from another plan" has bad.txt "tile-3.cells: from another plan"
check "and how to rerun them" has bad.txt "sbatch --array=1-3"
check "nothing written" test ! -e bad.ply
mv tile-1.saved site.plan-tiles/tile-1.cells
for k in 2 3; do "$lasmesh" tile site.plan.json --index "$k" -q; done
"$lasmesh" merge site.plan.json -o again/tileset.json -o again/mesh.ply -q
check "tiles rerun: the same PLY again" cmp -s one/mesh.ply again/mesh.ply
check "a rerun replaces, no other file" test "$(ls -A site.plan-tiles | wc -l)" -eq "$tiles"

# The index from the scheduler's environment, and refused when there is none or it is wrong.
rm site.plan-tiles/tile-0.cells
SLURM_ARRAY_TASK_ID=0 "$lasmesh" tile site.plan.json -q; rc=$?
check "SLURM_ARRAY_TASK_ID gives the tile" test "$rc" -eq 0 -a -s site.plan-tiles/tile-0.cells
rm site.plan-tiles/tile-0.cells
JOB_COMPLETION_INDEX=0 "$lasmesh" tile site.plan.json -q; rc=$?
check "JOB_COMPLETION_INDEX (Kubernetes) gives the tile" test "$rc" -eq 0 -a -s site.plan-tiles/tile-0.cells
env -u SLURM_ARRAY_TASK_ID -u JOB_COMPLETION_INDEX "$lasmesh" tile site.plan.json > noindex.txt 2>&1; rc=$?
check "no index: usage error (1)" test "$rc" -eq 1
check "asks for --index" has noindex.txt "give --index K"
"$lasmesh" tile site.plan.json --index "$tiles" > past.txt 2>&1; rc=$?
check "an index past the tiles: usage error" test "$rc" -eq 1
check "says the tiles there are" has past.txt "its tiles are 0 to $((tiles - 1))"

# An input whose header bounds leave out some of its points: the tile that finds one stops.
mkdir lie && cp deck-*.las lie/
last=$(ls lie/deck-*.las | tail -1)
python3 -c '
import struct, sys
f = open(sys.argv[1], "r+b"); f.seek(187); lo = struct.unpack("<d", f.read(8))[0]
f.seek(187); f.write(struct.pack("<d", lo + 8.0))' "$last"
"$lasmesh" plan lie/deck-*.las --tile 12 -o lie.json > /dev/null
failures=0
for k in $(seq 0 $(($(python3 -c 'import json; print(len(json.load(open("lie.json"))["tiles"]))') - 1))); do
  "$lasmesh" tile lie.json --index "$k" -q 2>> lie.txt || failures=$((failures + 1))
done
check "header bounds that lie: a tile stops (input error)" test "$failures" -ge 1
check "naming the file and the record" contains lie.txt "$(basename "$last"): point record [0-9]* lies at x"
check "saying its points would be lost" has lie.txt "its points would be lost"
# The record named is the one that lies there: its x, read from the file, is the x the message gives.
check "the record named holds the point named" python3 -c '
import re, struct, sys
found = re.findall(r"(\S+\.las): point record (\d+) lies at x ([-0-9.e]+)", open("lie.txt").read())
assert found
for path, record, x in found:
    f = open(path, "rb"); head = f.read(227)
    start, = struct.unpack_from("<I", head, 96); length, = struct.unpack_from("<H", head, 105)
    scale, = struct.unpack_from("<d", head, 131); offset, = struct.unpack_from("<d", head, 155)
    f.seek(start + int(record) * length); raw, = struct.unpack("<i", f.read(4))
    assert abs(raw * scale + offset - float(x)) < 1e-6, (path, record, x, raw * scale + offset)
'
"$lasmesh" merge lie.json -o lie.ply > lie-merge.txt 2>&1; rc=$?
check "merge then refuses (a tile missing), writing nothing" test "$rc" -eq 2 -a ! -e lie.ply

# An input changed since the plan.
cp deck-0_0.las saved.las && "$lasgen" --scene deck --points 1000 --seed 9 -o deck-0_0.las > /dev/null
"$lasmesh" tile site.plan.json --index 0 > changed.txt 2>&1; rc=$?
check "an input changed since the plan: input error" test "$rc" -eq 2
check "naming it" contains changed.txt "deck-0_0.las: changed since"
mv saved.las deck-0_0.las
"$lasmesh" plan - -o stdin.json < deck-0_0.las > stdin.txt 2>&1; rc=$?
check "plan of standard input: usage error" test "$rc" -eq 1
"$lasmesh" plan "${inputs[@]}" --scan-bounds -o scan.json > scan.txt 2>&1; rc=$?
check "plan has no --scan-bounds (it reads headers only): usage error" test "$rc" -eq 1
# A COPC file (laspy's simple.copc.laz: 1065 points in an octree of 65 chunks): each tile reads
# only the nodes that touch it, and the merged mesh is one run's.
copc=$here/../data/laz/laspy_simple.copc.laz
"$lasmesh" "$copc" --grid 48 -o copc-one.ply -q
"$lasmesh" plan "$copc" --grid 48 --tile 1200 -o copc.json > copc-plan.txt; rc=$?
check "plan of a COPC file: exit 0" test "$rc" -eq 0
check "plan: says the tiles read its octree nodes" has copc-plan.txt "1 COPC input: the tiles read only the octree nodes that touch them"
copc_times=$(sed -n 's/.*touch them, \([0-9.]*\)x its points in all/\1/p' copc-plan.txt)
check "plan: the tile jobs read the nodes' points, not the file's ($copc_times times)" \
  has copc-plan.txt "the tile jobs read the inputs' points $copc_times times in all"
check "plan: every tile lists some of its 65 chunks, every chunk some tile" python3 -c '
import json; p = json.load(open("copc.json")); seen = set()
assert len(p["tiles"]) >= 4, len(p["tiles"])
for t in p["tiles"]:
    c, = t["copc_chunks"]
    assert 0 < len(c["offsets"]) < 65 and sum(c["points"]) == t["points"], c
    seen.update(c["offsets"])
assert len(seen) == 65, len(seen)'
copc_tiles=$(python3 -c 'import json; print(len(json.load(open("copc.json"))["tiles"]))')
for k in $(seq 0 $((copc_tiles - 1))); do "$lasmesh" tile copc.json --index "$k" >> copc-tiles.txt 2>&1; done
check "tiles: each reads fewer than half the file's points" python3 -c '
import re; read = [int(n) for n in re.findall(r": (\d+) points read", open("copc-tiles.txt").read())]
assert len(read) == '"$copc_tiles"' and max(read) < 1065 / 2, read'
"$lasmesh" merge copc.json -o copc-many.ply -q; rc=$?
check "merge: exit 0" test "$rc" -eq 0
check "merged PLY = one run's PLY" cmp -s copc-one.ply copc-many.ply
# Cropped to the west half: nodes outside the grid are still read (by the tile nearest them), and
# each point outside is counted once, by the first tile that reads it.
crop=(--bounds 635000,848000,0,637300,854000,1000 --grid 48)
"$lasmesh" "$copc" "${crop[@]}" -o crop-one.ply > crop-one.txt 2>&1
"$lasmesh" plan "$copc" "${crop[@]}" --tile 1200 -o crop.json > /dev/null
for k in $(seq 0 $(($(python3 -c 'import json; print(len(json.load(open("crop.json"))["tiles"]))') - 1))); do
  "$lasmesh" tile crop.json --index "$k" -q
done
"$lasmesh" merge crop.json -o crop-many.ply > crop-many.txt 2>&1
check "cropped: some points outside the grid" contains crop-one.txt "^points  *1065 read, [1-9][0-9]* outside the grid"
check "cropped: merge counts the same points inside and outside" test "$(grep '^points ' crop-one.txt)" = "$(grep '^points ' crop-many.txt)"
check "cropped: the same PLY" cmp -s crop-one.ply crop-many.ply

finish tiles
