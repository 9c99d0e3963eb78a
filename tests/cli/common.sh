# SPDX-License-Identifier: Apache-2.0
# Shared by the command-line test scripts (sourced after they set lasmesh=...): a temporary
# folder removed at exit, named checks counted as they run, and a verdict at the end.
dir=$(mktemp -d) && trap 'chmod -R u+w "$dir"; rm -rf "$dir"' EXIT # chmod: tests make read-only folders
passed=0 failed=0

# check NAME COMMAND...: passes when the command succeeds.
check() { if "${@:2}"; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAILED: $1"; fi; }
contains() { grep -q -- "$2" "$1"; } # FILE REGEX
has() { grep -qF -- "$2" "$1"; }      # FILE TEXT (escape sequences, brackets)
lacks() { ! grep -qF -- "$2" "$1"; }  # FILE TEXT: the text is not there

# The scanned bounds of a LAS file as "minx,miny,minz maxx,maxy,maxz".
bounds() { "$lasmesh" info --json --scan "$1" | python3 -c '
import json, sys
s = json.load(sys.stdin)["scanned"]["bounds"]
print(",".join(map(str, s["min"])), ",".join(map(str, s["max"])))'; }

# shows_origin SUMMARY X,Y,Z: the summary's origin line gives the origin to the decimals it prints
# (a thousandth of a cell or finer), and prints at least one.
shows_origin() { python3 -c '
import re, sys
line = next(l for l in open(sys.argv[1]) if l.startswith("origin "))
shown = line.split()[1:4]
assert all("." in s for s in shown), shown
for s, exact in zip(shown, map(float, sys.argv[2].split(","))):
    assert abs(float(s) - exact) <= 0.5 * 10 ** -len(s.split(".")[1]) * (1 + 1e-9), (s, exact)' "$1" "$2"; }

# finish NAME: prints the tally; the script's exit status is whether every check passed.
finish() {
  echo "$1: $passed passed, $failed failed"
  [ "$failed" -eq 0 ]
}
