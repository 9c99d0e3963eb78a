#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# `lasmesh grid` and `lasmesh devices` as users run them. Usage: grid_test.sh LASMESH LASGEN
set -u
lasmesh=$1 lasgen=$2
source "$(dirname "$0")/common.sh"

"$lasmesh" devices > "$dir/devices.txt"
check "devices lists at least one device with its largest allocation" contains "$dir/devices.txt" "largest allocation"

"$lasgen" --scene sphere --points 50000 -o "$dir/s.las"
"$lasmesh" grid --json --grid 32 "$dir/s.las" > "$dir/file.json"
check "grid json" python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
assert d["dims"] == [32, 32, 32], d["dims"]
assert d["points_read"] == 50000 and d["points_outside"] == 0
assert 0 < d["occupied_cells"] < 32 ** 3
assert d["color"] == "8-bit in 16-bit fields"
' "$dir/file.json"
gzip -c "$dir/s.las" | "$lasmesh" grid --json --grid 32 --chunk-mb 0.01 - > "$dir/pipe.json"
check "gzip pipe with tiny slices gives the same grid" python3 -c '
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
for d in (a, b): d.pop("seconds")
assert a == b, (a, b)
' "$dir/file.json" "$dir/pipe.json"

# With no --grid, the grid meshing would use: chosen from the data, said why.
"$lasmesh" grid "$dir/s.las" > "$dir/auto.txt"
"$lasmesh" "$dir/s.las" -o "$dir/auto.ply" 2> "$dir/mesh.txt"
check "grid previews meshing's automatic grid" test "$(grep -o "cells of [0-9.]* (auto: .*" "$dir/auto.txt" | cut -d' ' -f3)" = \
  "$(grep -o "cells of [0-9.]* (auto: .*" "$dir/mesh.txt" | cut -d' ' -f3)"
check "grid says the grid was chosen from the data" contains "$dir/auto.txt" "(auto: "
"$lasmesh" grid --bounds 0,0,0,1,1,1 "$dir/s.las" > "$dir/out.txt"
check "points outside --bounds are counted" contains "$dir/out.txt" "points outside grid  50000 (100.000%)"

"$lasmesh" grid --grid 12x "$dir/s.las" 2> "$dir/err.txt"; rc=$?
check "bad --grid is a usage error" test "$rc" -eq 1
check "bad --grid is quoted" contains "$dir/err.txt" '"12x"'
"$lasmesh" grid --grid 4000 --max-memory 64 "$dir/s.las" 2> "$dir/err.txt"; rc=$?
check "too large a grid is refused" test "$rc" -eq 1
check "refusal suggests a grid" contains "$dir/err.txt" "would fit"
"$lasmesh" grid --device no-such-device "$dir/s.las" 2> "$dir/err.txt"; rc=$?
check "unknown device is a usage error" test "$rc" -eq 1
OCL_ICD_VENDORS=/nonexistent "$lasmesh" grid "$dir/s.las" 2> "$dir/err.txt"; rc=$?
check "no OpenCL platform exits 3" test "$rc" -eq 3
check "no platform names the package" contains "$dir/err.txt" "pocl-opencl-icd"

finish "cli grid"
