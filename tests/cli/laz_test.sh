#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# LAZ as users run it, on the small real files in tests/data/laz: a file, standard input and a
# gzip stream decode alike and mesh to the same bytes; LAZ that cannot be decoded is refused with
# exit code 2 and a message naming the file. (The larger corpus: corpus_test.sh.)
# Usage: laz_test.sh LASMESH SOURCE_DIR
set -u
lasmesh=$1 source_dir=$2
source "$(dirname "$0")/common.sh"
laz=$source_dir/tests/data/laz

simple=$laz/laspy_simple.laz
for f in "$simple" "$laz/laspy_simple.copc.laz" "$laz/pdal_lone-star_first_chunk.laz" "$laz/pdal_las_with_several_extra_byte_bloc_first_chunk.laz"; do
    "$lasmesh" info --json --scan "$f" | sed 1d > "$dir/file.json"
    "$lasmesh" info --json --scan - < "$f" | sed 1d > "$dir/stdin.json"
    gzip -c "$f" | "$lasmesh" info --json --scan - | sed 1d > "$dir/gz.json"
    check "$(basename "$f"): stdin equals file" cmp -s "$dir/file.json" "$dir/stdin.json"
    check "$(basename "$f"): gzip pipe equals file" cmp -s "$dir/file.json" "$dir/gz.json"
done
check "info reports the uncompressed format" python3 -c '
import json, subprocess, sys
d = json.loads(subprocess.run([sys.argv[1], "info", "--json", "--scan", sys.argv[2]], capture_output=True, text=True).stdout)
assert d["point_format"] == 7 and d["point_record_length"] == 36 and d["scanned"]["point_count"] == 1065, d
' "$lasmesh" "$laz/laspy_simple.copc.laz"
check "info names COPC" contains <("$lasmesh" info "$laz/laspy_simple.copc.laz") "^records              LAZ (LASzip-compressed), COPC"
check "info names LAZ" contains <("$lasmesh" info "$laz/laspy_simple.laz") "^records              LAZ (LASzip-compressed)$"
check "info gives the bounds to the scale's decimals" contains <("$lasmesh" info "$laz/laspy_simple.copc.laz") "^bounds min           635619.85 848899.70 406.59$"
check "info --json names COPC" contains <("$lasmesh" info --json "$laz/laspy_simple.copc.laz") '"records":"copc"'

# A whole mesh from LAZ: the file and a gzip stream give the same bytes.
lone=$laz/pdal_lone-star_first_chunk.laz
"$lasmesh" "$lone" -o "$dir/file.ply" -q
gzip -c "$lone" | "$lasmesh" - -o "$dir/gz.ply" -q
check "LAZ meshes (50,000 points of format 1)" test "$(stat -c %s "$dir/file.ply")" -gt 10000
check "LAZ from a file and from a gzip stream mesh to identical bytes" cmp -s "$dir/file.ply" "$dir/gz.ply"

# Colour fields that are 0 in every record (laspy's plane.laz): no colour, not an all-black mesh.
"$lasmesh" "$laz/laspy_plane.laz" -o "$dir/plane.ply" 2> "$dir/plane.txt"
check "all-zero colour: the mesh has no colour" test -z "$(head -c 300 "$dir/plane.ply" | grep -a 'property uchar red')"
check "all-zero colour: said so" has "$dir/plane.txt" "the colour of every point is 0 (black): the mesh has no colour"
check "all-zero colour: the summary says no colour" has "$dir/plane.txt" "triangles, no colour"

head -c 5000 "$simple" > "$dir/cut.laz"
"$lasmesh" info --scan "$dir/cut.laz" > /dev/null 2> "$dir/cut.err"
check "truncated LAZ: exit code 2" [ $? -eq 2 ]
check "truncated LAZ: one line naming the file" [ "$(wc -l < "$dir/cut.err")" -eq 1 ]
head -c 5000 "$simple" | "$lasmesh" info --scan - > /dev/null 2> "$dir/cutpipe.err"
check "truncated LAZ pipe: names the chunk and the byte" contains "$dir/cutpipe.err" "LAZ chunk 1.*at byte"
finish laz_test
