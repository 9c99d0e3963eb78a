#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# `lasmesh info` as users run it: file, stdin and compressed pipes agree; errors exit non-zero
# with a message naming the input. Usage: info_test.sh LASMESH LASGEN
set -u
lasmesh=$1 lasgen=$2
source "$(dirname "$0")/common.sh"
same() { cmp -s "$1" "$2"; }

"$lasgen" --scene torus --points 30000 --las-version 1.4 --format 7 -o "$dir/t.las"
"$lasmesh" info --json --scan "$dir/t.las" > "$dir/file.json"
check "json has the documented keys" python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
assert set(d) == {"version", "records", "point_format", "point_record_length", "point_count", "scale", "offset",
                  "bounds", "has_color", "crs", "vlrs", "evlr_count", "crs_evlrs", "scanned"}, sorted(d)
assert d["crs"] is None, d["crs"]
assert d["records"] == "las", d["records"]
assert d["version"] == "1.4" and d["point_format"] == 7 and d["point_count"] == 30000
assert d["scanned"]["point_count"] == 30000 and d["has_color"] is True
assert set(d["scanned"]) == {"point_count", "bounds", "color_min", "color_max"}
assert d["vlrs"][0]["user_id"] == "lasmesh"
' "$dir/file.json"

"$lasmesh" info --json --scan - < "$dir/t.las" > "$dir/stdin.json"
check "stdin equals file" same "$dir/file.json" "$dir/stdin.json"
"$lasmesh" info --json --scan --chunk-points 1 "$dir/t.las" > "$dir/chunk1.json"
check "chunk size 1 equals default" same "$dir/file.json" "$dir/chunk1.json"
for z in "gzip -c" "bzip2 -c" "xz -c" "zstd -q -c"; do
    $z < "$dir/t.las" | "$lasmesh" info --json --scan - > "$dir/z.json"
    check "$z pipe equals file" same "$dir/file.json" "$dir/z.json"
done
zstd -q -c < "$dir/t.las" > "$dir/t.las.zst"
"$lasmesh" info --json --scan "$dir/t.las.zst" > "$dir/zfile.json"
check "zstd file equals plain file" same "$dir/file.json" "$dir/zfile.json"
"$lasmesh" info "$dir/t.las.zst" > "$dir/text.txt"
check "text output names the compression" contains "$dir/text.txt" "(zstd)"

"$lasgen" --scene sphere --points 100 -o - | "$lasmesh" info --scan - > "$dir/pipe.txt"
check "generator pipes into info" contains "$dir/pipe.txt" "scanned point count  100"

# Errors: non-zero exit, one line naming the input and what is wrong.
head -c 1000 "$dir/t.las" > "$dir/cut.las"
"$lasmesh" info --scan "$dir/cut.las" 2> "$dir/err.txt"; rc=$?
check "truncated file exits 2" test "$rc" -eq 2
check "truncated file message" contains "$dir/err.txt" "cut.las: ends at byte 1000 after"
head -c 5000 "$dir/t.las" | "$lasmesh" info --scan - 2> "$dir/err.txt"; rc=$?
check "truncated pipe exits 2" test "$rc" -eq 2
check "truncated pipe message" contains "$dir/err.txt" "standard input: ends at byte 5000"
"$lasmesh" info - < /dev/null 2> "$dir/err.txt"; rc=$?
check "empty stdin exits 2" test "$rc" -eq 2
check "empty stdin message" contains "$dir/err.txt" "standard input: is empty"
"$lasmesh" info "$dir/missing.las" 2> "$dir/err.txt"; rc=$?
check "missing file exits 2" test "$rc" -eq 2
"$lasmesh" info --no-such-option "$dir/t.las" 2> "$dir/err.txt"; rc=$?
check "unknown option is a usage error" test "$rc" -eq 1
check "usage error quotes the option" contains "$dir/err.txt" "no-such-option"
"$lasmesh" --help > "$dir/help.txt"; rc=$?
check "help exits 0" test "$rc" -eq 0
check "help lists info" contains "$dir/help.txt" "info"
"$lasmesh" --version > "$dir/version.txt"
check "version" contains "$dir/version.txt" "lasmesh "

# lasgen sizes its batches by bytes and by the points asked: 100 records of 65,535 bytes fit in a
# gigabyte of address space (a batch of 2^18 of them took 17 GB).
(ulimit -v 1000000; "$lasgen" --scene sphere --points 100 --extra-bytes 65501 -o "$dir/long.las")
check "lasgen: 100 records of 65,535 bytes within 1 GB of address space" test "$(stat -c %s "$dir/long.las" 2> /dev/null)" -gt 6500000
# Coordinate systems: named with their EPSG code and unit, in text and JSON; meshing records them
# in the outputs; degrees are projected to the UTM zone of the data's centre.
"$lasgen" --scene box --points 2000 --epsg 32631 --origin 431250,6700200,10 -o "$dir/utm.las"
"$lasmesh" info "$dir/utm.las" > "$dir/utm.txt"
check "info names the CRS" has "$dir/utm.txt" "crs                  WGS 84 / UTM zone 31N (EPSG:32631), projected, in metre"
"$lasmesh" info "$dir/t.las" > "$dir/none.txt"
check "info says when there is none" has "$dir/none.txt" "crs                  none declared"
check "info --json gives the CRS's parts" python3 -c '
import json, sys
c = json.load(sys.stdin)["crs"]
assert (c["code"], c["kind"], c["unit"], c["unit_metres"], c["source"]) == ("EPSG:32631", "projected", "metre", 1.0, "GeoTIFF keys"), c
assert "UTM zone 31N" in c["wkt"], c' < <("$lasmesh" info --json "$dir/utm.las")
"$lasgen" --scene box --points 2000 --epsg 2992 --origin 7600000,700000,100 -o "$dir/ft.las"
check "feet are named with their length" contains <("$lasmesh" info "$dir/ft.las") "in foot (0.3048 m)"
"$lasmesh" "$dir/utm.las" -o "$dir/utm.ply" --ascii --grid 32 2> "$dir/utm-summary.txt"
check "the PLY records the CRS" has "$dir/utm.ply" "comment crs EPSG:32631"
check "the summary names it" has "$dir/utm-summary.txt" "crs            WGS 84 / UTM zone 31N (EPSG:32631)"
"$lasgen" --scene box --points 2000 --epsg 4326 --origin 5,60,10 --size 0.01 -o "$dir/deg.las"
"$lasmesh" "$dir/deg.las" -o "$dir/deg.ply" --ascii 2> "$dir/deg.txt"; rc=$?
check "degrees: meshed (exit 0, got $rc)" test "$rc" -eq 0
# 5 E, 60 N lies in zone 31 by its 6 degrees, but in 32V by the UTM grid's exception for Norway.
check "... in the UTM zone of the centre, saying so" has "$dir/deg.txt" "crs            WGS 84 / UTM zone 32N (EPSG:32632), projected, in metre (projected from WGS 84 (EPSG:4326)"
check "... which the PLY records" has "$dir/deg.ply" "comment crs EPSG:32632"
"$lasmesh" "$dir/deg.las" -o "$dir/deg31.ply" --crs EPSG:32631 2> /dev/null
check "--crs: the CRS asked for" has "$dir/deg31.ply" "comment crs EPSG:32631"
"$lasmesh" "$dir/deg.las" -o "$dir/bad.ply" --crs EPSG:999999 2> "$dir/bad.txt"; rc=$?
check "--crs unknown: exit 1, named" test "$rc" -eq 1 -a ! -e "$dir/bad.ply"
check "... with the flag" has "$dir/bad.txt" "(--crs)"

finish "cli info"
