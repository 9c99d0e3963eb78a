#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# `lasmesh compare` end to end, and the fidelity the mesher promises on the deck scene: at
# --grid 256 the mesh stays on average within about half a cell of the points, both ways,
# covers what they cover, and leaves the floating outlier clusters out.
# Usage: compare_test.sh LASMESH LASGEN
set -u
lasmesh=$1 lasgen=$2 here=$(dirname "$0")
source "$(dirname "$0")/common.sh"
field() { python3 -c "import json, sys; r = json.load(open(sys.argv[1])); print(eval('r' + sys.argv[2]))" "$@"; }

"$lasgen" --scene deck --points 1000000 -o "$dir/deck.las"
"$lasmesh" "$dir/deck.las" --grid 256 -o "$dir/deck.ply" -o "$dir/deck.drc" -o "$dir/deck.glb" 2> /dev/null
"$lasmesh" compare "$dir/deck.ply" "$dir/deck.las" --json > "$dir/c.json"
check "compare succeeds" test -s "$dir/c.json"
cell=$(field "$dir/c.json" '["cell_size"]')
c2m=$(field "$dir/c.json" '["cloud_to_mesh"]["mean"]')
m2c=$(field "$dir/c.json" '["mesh_to_cloud"]["mean"]')
echo "deck at grid 256: cell $cell, mean cloud to mesh $c2m, mesh to cloud $m2c"
check "cloud to mesh: mean within about half a cell" python3 -c "assert $c2m < 0.55 * $cell"
# The default sheet lies on the points: most of them within a tenth of a cell.
check "sheet: median cloud to mesh under a tenth of a cell" python3 -c "assert $(field "$dir/c.json" '["cloud_to_mesh"]["median"]') < 0.1 * $cell"
check "mesh to cloud: mean within about half a cell" python3 -c "assert $m2c < 0.55 * $cell"
# Coverage: every point but the outlier clusters (class 7, about 0.4% of them) lies within two
# cells, less a tenth of a percent. (At these 25 cm cells the pipe riser, 25 cm in radius, is a
# ring of cells meshed in pieces that corners past the points join: were sheets cut back to
# their points there too, its upper pieces would fall to small-piece removal, 0.22% of the
# points.)
outliers=$(python3 -c '
import struct, sys
d = open(sys.argv[1], "rb").read()
at, length, n = struct.unpack_from("<I", d, 96)[0], struct.unpack_from("<H", d, 105)[0], struct.unpack_from("<I", d, 107)[0]
print(sum(d[at + i * length + 15] & 31 == 7 for i in range(n)) / n)' "$dir/deck.las")
within2=$(field "$dir/c.json" '["cloud_to_mesh"]["within_2_cells"]')
check "every surface covered ($within2 within 2 cells, $outliers of the points outliers)" python3 -c "assert $within2 > 1 - $outliers - 0.001"
check "outlier clusters not meshed (metres away)" python3 -c "assert $(field "$dir/c.json" '["cloud_to_mesh"]["max"]') > 5"
check "every sample used" test "$(field "$dir/c.json" '["points_used"]')" = 1000000
# The compressed outputs measure the same, to within their quantization step (under a tenth
# of a cell).
for ext in drc glb; do
  "$lasmesh" compare "$dir/deck.$ext" "$dir/deck.las" --cell-size "$cell" --json > "$dir/$ext.json"
  check "compare reads the .$ext" python3 -c "assert abs($(field "$dir/$ext.json" '["cloud_to_mesh"]["mean"]') - $c2m) < 0.02 * $cell"
done
# The classic level-set placement wraps the thin surfaces a cell wide: the measure tells.
"$lasmesh" "$dir/deck.las" --grid 256 --surface closed --placement iso -o "$dir/iso.ply" 2> /dev/null
"$lasmesh" compare "$dir/iso.ply" "$dir/deck.las" --json > "$dir/iso.json"
check "iso placement measured farther" python3 -c "assert $(field "$dir/iso.json" '["cloud_to_mesh"]["mean"]') > 1.5 * $c2m"

# Text report, a sample of the points, a heat map; the same numbers from stdin.
"$lasmesh" "$dir/deck.las" --grid 256 --surface closed -o "$dir/closed.ply" 2> /dev/null
"$lasmesh" compare "$dir/closed.ply" "$dir/deck.las" --samples 50000 --heatmap "$dir/heat.ply" > "$dir/c.txt" 2> "$dir/log.txt"
check "text report names both directions" contains "$dir/c.txt" "mesh to cloud"
check "text report gives the points used" contains "$dir/c.txt" "1000000 points, 50000 used"
check "heat map legend" contains "$dir/log.txt" "red 0.5"
check "heat map is a closed coloured mesh" python3 "$here/ply_check.py" "$dir/heat.ply" 0,0,0 0,0,0 1e9
gzip -c "$dir/deck.las" | "$lasmesh" compare "$dir/closed.ply" - --samples 50000 > "$dir/stdin.txt" 2> /dev/null
check "stdin and gzip give the same report" diff <(tail -n +5 "$dir/c.txt") <(tail -n +5 "$dir/stdin.txt")
"$lasmesh" compare "$dir/deck.ply" "$dir/deck.las" --samples 50000 --json > "$dir/a.json"
# The answer first: the median and the shares within a cell of the JSON, in a sentence, with the unit.
"$lasmesh" compare "$dir/deck.ply" "$dir/deck.las" --samples 50000 > "$dir/a.txt"
check "text report starts with the verdict" python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))["cloud_to_mesh"]
first, second = open(sys.argv[2]).read().split("\n")[:2]
want = "verdict        half of the points lie within %.4g of the mesh" % d["median"]
assert first.startswith(want), (first, want)
assert ("%.4g%% within a cell" % (100 * d["within_1_cell"])) in first, first
assert second.startswith("units          the file") and "declares no CRS" in second, second
' "$dir/a.json" "$dir/a.txt"
OMP_NUM_THREADS=1 taskset -c 0 "$lasmesh" compare "$dir/deck.ply" "$dir/deck.las" --samples 50000 --json > "$dir/b.json"
check "one core gives the same numbers" cmp -s "$dir/a.json" "$dir/b.json"

# Errors.
"$lasmesh" compare "$dir/missing.ply" "$dir/deck.las" 2> "$dir/err.txt"; rc=$?
check "missing mesh exits 2" test "$rc" -eq 2
check "missing mesh named" contains "$dir/err.txt" "missing.ply"
"$lasmesh" compare "$dir/deck.las" "$dir/deck.las" 2> "$dir/err.txt"; rc=$?
check "unknown mesh extension exits 1" test "$rc" -eq 1
head -c 1000 "$dir/deck.ply" > "$dir/cut.ply"
"$lasmesh" compare "$dir/cut.ply" "$dir/deck.las" 2> "$dir/err.txt"; rc=$?
check "truncated mesh exits 2" test "$rc" -eq 2
check "truncated mesh: says where" contains "$dir/err.txt" "cut.ply: byte"
"$lasmesh" compare "$dir/deck.ply" "$dir/deck.las" --heatmap "$dir/no/dir/h.ply" 2> /dev/null; rc=$?
check "heat map into a missing folder exits 4" test "$rc" -eq 4

# With a CRS: lengths in its unit, named; a cloud in another CRS is brought into the mesh's, one
# without a CRS is warned about.
"$lasgen" --scene box --points 20000 --epsg 32631 --origin 431250,6700200,10 -o "$dir/utm.las"
"$lasmesh" "$dir/utm.las" -o "$dir/utm.ply" --grid 32 -q
"$lasmesh" compare "$dir/utm.ply" "$dir/utm.las" --samples 5000 --mesh-samples 5000 > "$dir/utm.txt" 2> "$dir/utm.err"
check "units named from the CRS" has "$dir/utm.txt" "units          metre (the cloud's CRS: WGS 84 / UTM zone 31N, EPSG:32631); every length below too"
check "no warning when mesh and cloud agree" test ! -s "$dir/utm.err"
"$lasgen" --scene box --points 20000 --epsg 32632 --origin 431250,6700200,10 -o "$dir/utm32.las"
"$lasmesh" compare "$dir/utm.ply" "$dir/utm32.las" --samples 5000 --mesh-samples 5000 > /dev/null 2> "$dir/other.err"
check "a cloud in another CRS is brought into the mesh's" has "$dir/other.err" "note: the cloud was brought from WGS 84 / UTM zone 32N (EPSG:32632), projected, in metre to WGS 84 / UTM zone 31N (EPSG:32631)"
"$lasgen" --scene box --points 20000 --origin 431250,6700200,10 -o "$dir/none.las"
"$lasmesh" compare "$dir/utm.ply" "$dir/none.las" --samples 5000 --mesh-samples 5000 > /dev/null 2> "$dir/none.err"
check "a cloud without a CRS is warned about" has "$dir/none.err" "the mesh records the CRS EPSG:32631 but the cloud declares none"

finish "cli compare"
