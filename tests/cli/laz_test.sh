#!/usr/bin/env bash
# LAZ as users run it (issue 18): a LAZ file meshes to the same bytes as its LAS twin; pipes and
# gzip streams decode like the file; LAZ that cannot be decoded is refused with exit code 2 and
# a message naming the file. Uses ../shared/data/laz; skipped when it is absent.
# Usage: laz_test.sh LASMESH SOURCE_DIR
set -u
lasmesh=$1 source_dir=$2
source "$(dirname "$0")/common.sh"
laz=${LASMESH_SHARED:-$source_dir/../shared}/data/laz
if [ ! -f "$laz/MANIFEST.tsv" ]; then echo "laz_test: skipped, $laz/MANIFEST.tsv is absent"; exit 0; fi

simple=$laz/laspy_laspy__tests_data_simple.laz
# autzen_trim: 110,000 points in 3 chunks, decoded in parallel; its twin is in the LAS corpus.
autzen=$laz/PDAL_PDAL__test_data_laz_autzen_trim.laz
"$lasmesh" "$autzen" -o "$dir/laz.ply" --grid 128 > /dev/null 2>&1
"$lasmesh" "$laz/../las/PDAL_PDAL__test_data_las_autzen_trim.las" -o "$dir/las.ply" --grid 128 > /dev/null 2>&1
check "LAZ and its LAS twin mesh to identical bytes" cmp -s "$dir/laz.ply" "$dir/las.ply"
check "the mesh is not empty" [ "$(stat -c %s "$dir/laz.ply")" -gt 100000 ]

for f in "$simple" "$laz/laspy_laspy__tests_data_simple.copc.laz" "$laz/PDAL_PDAL__test_data_ept_source_lone-star.laz"; do
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
' "$lasmesh" "$laz/laspy_laspy__tests_data_simple.copc.laz"

old=$laz/PDAL_PDAL__test_data_laz_simple-laszip-compressor-version-1.2r0.laz
"$lasmesh" info --scan "$old" > /dev/null 2> "$dir/old.err"
check "LASzip 1.x items: exit code 2" [ $? -eq 2 ]
check "LASzip 1.x items: message names the file and the item" contains "$dir/old.err" "simple-laszip-compressor-version-1.2r0.laz.*POINT10 v1"
head -c 5000 "$simple" > "$dir/cut.laz"
"$lasmesh" info --scan "$dir/cut.laz" > /dev/null 2> "$dir/cut.err"
check "truncated LAZ: exit code 2" [ $? -eq 2 ]
check "truncated LAZ: one line naming the file" [ "$(wc -l < "$dir/cut.err")" -eq 1 ]
head -c 5000 "$simple" | "$lasmesh" info --scan - > /dev/null 2> "$dir/cutpipe.err"
check "truncated LAZ pipe: names the chunk and the byte" contains "$dir/cutpipe.err" "LAZ chunk 1.*at byte"
finish laz_test
