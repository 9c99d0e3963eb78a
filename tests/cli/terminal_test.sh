#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The terminal behaviour for real: under a pseudo-terminal (script(1)) a progress line is drawn
# in place; redirected to a file, never; --quiet silences everything but errors; --report
# writes the summary as JSON; --verbose adds stage details.
# Usage: terminal_test.sh LASMESH LASGEN
set -u
lasmesh=$1 lasgen=$2
source "$(dirname "$0")/common.sh"
erase=$'\r\e[K'

"$lasgen" --scene deck --points 300000 -o "$dir/d.las"
# script -c runs the command with a pseudo-terminal as its stdin, stdout and stderr. The input
# comes through a pipe that stalls for a moment, so the line is redrawn with a rate.
script -qfec "'$lasmesh' '$dir/d.las' -o '$dir/tty.ply' --grid 128" /dev/null > "$dir/tty.txt" 2>&1
check "progress drawn on a terminal" has "$dir/tty.txt" "${erase}reading   "
check "progress gives the file's bytes" contains "$dir/tty.txt" "MB of 10.2 MB"
check "progress names the stages" has "$dir/tty.txt" "${erase}extracting the surface"
check "progress names the steps of extraction" has "$dir/tty.txt" "${erase}simplifying "
check "numbers for people: the cell in four digits" contains "$dir/tty.txt" "cells of [0-9]*\.[0-9]\{1,4\}[^0-9]"
check "numbers for people: megabytes with one decimal" contains "$dir/tty.txt" "bricks of 64, [0-9]*\.[0-9] MB of grid"
check "progress line erased before the summary" has "$dir/tty.txt" "${erase}input          "
script -qfec "{ head -c 3000000 '$dir/d.las'; sleep 0.6; tail -c +3000001 '$dir/d.las'; } |
  '$lasmesh' - -o '$dir/pipe.ply' --grid 128 --chunk-mb 1" /dev/null > "$dir/pipe.txt" 2>&1
check "progress gives a rate and the time left" contains "$dir/pipe.txt" "points/s, [0-9]*:[0-5][0-9]:[0-5][0-9] left"

# compare shows its steps too, and erases the line before its report.
script -qfec "'$lasmesh' compare '$dir/tty.ply' '$dir/d.las'" /dev/null > "$dir/compare.txt" 2>&1
check "compare draws its steps on a terminal" has "$dir/compare.txt" "${erase}measuring cloud to mesh (300000 points)"
check "compare erases the line before its report" has "$dir/compare.txt" "${erase}verdict        "
"$lasmesh" compare "$dir/tty.ply" "$dir/d.las" > "$dir/compare-file.txt" 2>&1
check "compare draws nothing into a file" lacks "$dir/compare-file.txt" "measuring"

# A run that fails after the progress line was drawn: the line is erased before the error.
script -qfec "'$lasmesh' '$dir/d.las' -o '$dir/none.ply' --grid 128 --min-piece 1e9" /dev/null > "$dir/fail.txt" 2>&1
check "progress line erased before an error" has "$dir/fail.txt" "${erase}lasmesh: $dir/d.las: the mesh is empty"

"$lasmesh" "$dir/d.las" -o "$dir/file.ply" --grid 128 2> "$dir/err.txt"
check "no progress in redirected output" test "$(grep -c $'\e' "$dir/err.txt")" -eq 0
check "summary still there" contains "$dir/err.txt" "^mesh "
check "same mesh with or without a terminal" cmp -s "$dir/tty.ply" "$dir/file.ply"

script -qfec "'$lasmesh' '$dir/d.las' -o '$dir/q.ply' --grid 128 --quiet" /dev/null > "$dir/quiet.txt" 2>&1
check "--quiet: nothing on a terminal" test ! -s "$dir/quiet.txt"
check "--quiet still writes the mesh" test -s "$dir/q.ply"
"$lasmesh" "$dir/d.las" -o "$dir/q.ply" --grid 128 -q --iso nonsense 2> "$dir/err.txt"; rc=$?
check "--quiet keeps errors" test "$rc" -eq 1 -a -s "$dir/err.txt"

"$lasmesh" "$dir/d.las" -o "$dir/v.ply" -o "$dir/v.drc" --grid 128 -v --report "$dir/r.json" 2> "$dir/verbose.txt"
check "--verbose names the device memory" contains "$dir/verbose.txt" "^device .*largest buffer"
check "--verbose times each output" contains "$dir/verbose.txt" "^wrote          $dir/v.drc in"
check "summary gives the peak memory" contains "$dir/verbose.txt" "^memory .* MB peak resident"
check "--report is JSON with every field" python3 - "$dir/r.json" "$dir" <<'PY'
import json, os, sys
r = json.load(open(sys.argv[1]))
d = sys.argv[2]
assert r["input"] == d + "/d.las", r["input"]
assert r["points_read"] == 300000 and r["points_outside"] == 0
assert r["grid"]["dims"][0] == 128 and r["grid"]["cell_size"] > 0 and len(r["grid"]["origin"]) == 3
assert r["iso"] >= 1 and r["iso_auto"] is True
assert r["vertices"] > 0 and r["triangles"] > 0
assert [o["path"] for o in r["outputs"]] == [d + "/v.ply", d + "/v.drc"]
assert all(o["bytes"] == os.path.getsize(o["path"]) for o in r["outputs"])
s = r["seconds"]
assert 0 < s["read_accumulate"] <= s["total"] and s["extract"] > 0 and s["write"] > 0
assert r["peak_rss_bytes"] > 10**7
PY
"$lasmesh" "$dir/d.las" -o "$dir/v.ply" --report "$dir/none/r.json" 2> "$dir/err.txt"; rc=$?
check "--report into a missing folder exits 4 before reading" test "$rc" -eq 4

finish "cli terminal"
