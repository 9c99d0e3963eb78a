#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# A survey of many files against the single file holding the same points (lasgen --split):
#   1. the deck in 64 LAS files in the single file's frame: identical mesh bytes; read+accumulate
#      and total time against the single file (best of 3 each, same run), and `cat` of each;
#   2. the same 64 files with their own offsets (whole metres apart), odd files at half the scale,
#      a third in point format 2 and a third in format 7 (LAS 1.4), every fourth one zstd: the mean
#      distance of its mesh's vertices to the single file's mesh, both unsimplified, in cells
#      (`lasmesh compare` with the vertices as the cloud), and its time; for scale, the same
#      distance for the single file written at half the scale;
#   3. 10,000 files of POINTS / 10,000 points each: peak resident memory against the single file;
#   4. 128 small LAZ files of one chunk each, decoded one at a time and several at once.
# Usage: tools/bench_survey.sh [POINTS]   (default 5,000,000)
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/bench_common.sh
n=${1:-5000000}
work=$(mktemp -d) && trap 'rm -rf "$work"' EXIT
lasmesh=build/lasmesh lasgen=build/lasgen

"$lasgen" -n "$n" --order scan -o "$work/deck.las"
"$lasgen" -n "$n" --order scan --split 64 -o "$work/same.las"
"$lasgen" -n "$n" --order scan --split 64 --split-vary -o "$work/vary.las"
for k in $(seq 0 4 63); do zstd -q -1 --rm "$work/vary-$(printf %02d "$k").las"; done

# report FILE KEY: a number from a --report JSON ("seconds.total").
report() { python3 -c "import json, sys; r = json.load(open(sys.argv[1]))
for k in sys.argv[2].split('.'): r = r[k]
print(r)" "$1" "$2"; }
# best_run NAME ARGS...: best of 3 runs' read+accumulate and total seconds, from their reports.
best_run() {
  local name=$1 read=999 total=999 json="$work/${1//[^a-z0-9]/_}.json"
  shift
  for _ in 1 2 3; do
    "$lasmesh" "$@" -q --report "$json"
    read=$(echo "r = $(report "$json" seconds.read_accumulate); if (r < $read) r else $read" | bc -l)
    total=$(echo "t = $(report "$json" seconds.total); if (t < $total) t else $total" | bc -l)
  done
  printf "%-34s read+accumulate %6.3f s, total %6.3f s, peak %s MB\n" "$name" "$read" "$total" \
    "$(echo "$(report "$json" peak_rss_bytes) / 1000000" | bc)"
}

echo "points: $n; $(nproc) cores"
printf "%-34s %6.3f s\n" "cat deck.las" "$(best cat "$work/deck.las")"
printf "%-34s %6.3f s\n" "cat same-*.las (64 files)" "$(best cat "$work"/same-*.las)"
best_run "single file" "$work/deck.las" -o "$work/deck.ply"
best_run "64 files, one frame" "$work"/same-*.las -o "$work/same.ply"
if cmp -s "$work/deck.ply" "$work/same.ply"; then echo "64 files, one frame: identical bytes"; else echo "64 files, one frame: BYTES DIFFER"; fi
best_run "64 files, own frames, 16 zstd" "$work"/vary-* -o "$work/vary.ply"

# vertices_as_las MESH.ply CLOUD.las: the vertices of a binary PLY as a LAS cloud.
vertices_as_las() { python3 - "$1" "$2" <<'EOF'
import struct, sys
data = open(sys.argv[1], "rb").read()
end = data.index(b"end_header\n") + len(b"end_header\n")
header = data[:end].decode("ascii").splitlines()
origin = [float(v) for v in next(l for l in header if l.startswith("comment origin")).split()[2:]]
count = int(next(l for l in header if l.startswith("element vertex")).split()[2])
stride = 12 + 12 * ("property float nx" in header) + 3 * ("property uchar red" in header)
scale = 0.00001
points = [struct.unpack_from("<3f", data, end + v * stride) for v in range(count)]
raw = [[round(p[a] / scale) for a in range(3)] for p in points]
lo = [min(r[a] for r in raw) * scale + origin[a] for a in range(3)]
hi = [max(r[a] for r in raw) * scale + origin[a] for a in range(3)]
head = bytearray(227); head[0:4] = b"LASF"; head[24] = 1; head[25] = 2
struct.pack_into("<HII", head, 94, 227, 227, 0); head[104] = 0
struct.pack_into("<HI", head, 105, 20, count)
struct.pack_into("<3d", head, 131, scale, scale, scale)
struct.pack_into("<3d", head, 155, *origin)
struct.pack_into("<6d", head, 179, hi[0], lo[0], hi[1], lo[1], hi[2], lo[2])
body = b"".join(struct.pack("<3i8x", *r) for r in raw)
open(sys.argv[2], "wb").write(bytes(head) + body)
EOF
}

# The vertices of the 64-file mesh as a cloud, compared with the single file's mesh: both
# unsimplified (two simplifications of slightly different surfaces choose different triangles).
"$lasmesh" "$work/deck.las" -o "$work/deck0.ply" --simplify 0 -q
"$lasmesh" "$work"/vary-* -o "$work/vary0.ply" --simplify 0 -q
# mean_distance MESH.ply: the mean distance of its vertices to the single file's unsimplified mesh.
mean_distance() {
  vertices_as_las "$1" "$work/vertices.las"
  "$lasmesh" compare "$work/deck0.ply" "$work/vertices.las" --json 2> /dev/null |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["cloud_to_mesh"]["mean"])'
}
cell=$(report "$work/single_file.json" grid.cell_size)
mean=$(mean_distance "$work/vary0.ply")
printf "own frames: vertices to the single file's mesh: mean %.5f (%.4f cell of %.4f)\n" "$mean" \
  "$(echo "$mean / $cell" | bc -l)" "$cell"
# For scale: the single file written at half the scale (its points rounded to 0.5 mm, not 1 mm).
"$lasgen" -n "$n" --order scan --scale 0.0005 -o "$work/half.las"
"$lasmesh" "$work/half.las" -o "$work/half0.ply" --simplify 0 -q
mean=$(mean_distance "$work/half0.ply")
printf "the single file at half the scale: mean %.5f (%.4f cell)\n" "$mean" "$(echo "$mean / $cell" | bc -l)"

# 10,000 small files: memory follows the grid, not the number of files.
rm -f "$work"/same-*.las "$work"/vary-*
"$lasgen" -n "$n" --order scan --split 10000 -o "$work/small.las"
ls "$work"/small-*.las > "$work/small.txt"
best_run "10,000 files (--inputs)" --inputs "$work/small.txt" -o "$work/small.ply"
if cmp -s "$work/deck.ply" "$work/small.ply"; then echo "10,000 files: identical bytes"; else echo "10,000 files: BYTES DIFFER"; fi

# Small LAZ files, one chunk each (128 copies of tests/data/laz/laspy_plane.laz, 28,185 points):
# one file at a time (--threads 1) against several decoded at once (every core).
rm -f "$work"/small-*.las
for k in $(seq -w 1 128); do cp tests/data/laz/laspy_plane.laz "$work/plane-$k.laz"; done
best_run "128 LAZ files, one at a time" "$work"/plane-*.laz --grid 256 --threads 1 -o "$work/plane1.ply"
best_run "128 LAZ files, several at once" "$work"/plane-*.laz --grid 256 -o "$work/plane.ply"
if cmp -s "$work/plane1.ply" "$work/plane.ply"; then echo "LAZ files: identical bytes"; else echo "LAZ files: BYTES DIFFER"; fi
