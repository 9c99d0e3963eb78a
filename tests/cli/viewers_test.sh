#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The outputs open in the programs users open them with, headless, each required (tools/test.sh
# installs them): the Khronos validator, assimp (assimp-utils; Open3D and many viewers
# read glTF through it), Open3D (python3-open3d). Then all-or-nothing outputs and the empty-mesh
# error. Usage: viewers_test.sh LASMESH LASGEN VALIDATOR_FOLDER
set -u
lasmesh=$1 lasgen=$2 validator=$3 here=$(dirname "$0")
source "$(dirname "$0")/common.sh"
ply_count() { sed -n "s/^element $2 //p" "$1" | head -n 1; }

"$lasgen" --scene deck --points 300000 -o "$dir/deck.las" > /dev/null
# --min-piece 0 keeps the outlier clusters, so the mesh spans the whole cloud for the bounds check.
"$lasmesh" "$dir/deck.las" --grid 128 --min-piece 0 -o "$dir/deck.ply" -o "$dir/deck.glb" 2> "$dir/summary.txt"
"$lasmesh" "$dir/deck.las" --grid 128 --min-piece 0 -o "$dir/draco.glb" --glb-compression draco 2> /dev/null
faces=$(ply_count "$dir/deck.ply" face) vertices=$(ply_count "$dir/deck.ply" vertex)
check "summary mentions normals" contains "$dir/summary.txt" "triangles, coloured, normals"
read -r lo hi < <(bounds "$dir/deck.las")
check "PLY has unit normals that agree with the winding" env OPEN=1 python3 "$here/ply_check.py" "$dir/deck.ply" "$lo" "$hi" 0.51
read -r origin positions indices < <(python3 "$here/glb_check.py" "$dir/deck.glb" "$dir/unused.drc")
check "plain .glb passes glb_check.py" test -n "${indices:-}"
check "plain .glb has the PLY's faces and vertices" test "$((indices / 3)) $positions" = "$faces $vertices"
check "plain .glb keeps the origin in extras, not in a translation" test -z "$(grep -a '"translation"' "$dir/deck.glb")"
check "the extras give the summary's origin" shows_origin "$dir/summary.txt" "$origin"
check "plain .glb is named after the input" grep -qa '"name":"deck"' "$dir/deck.glb"

# Every reader below is installed by tools/test.sh: one that is missing fails the test, so a
# .glb nothing checked never passes.
node "$here/gltf_validate.js" "$validator" "$dir/deck.glb" > "$dir/validator.txt"; rc=$?
cat "$dir/validator.txt"
check "glTF validator: plain .glb, no errors (exit 2: the validator is missing; tools/test.sh installs it)" test "$rc" -eq 0
check "validator: no warnings on NORMAL (unit length)" test -z "$(grep -i 'NORMAL' "$dir/validator.txt" | grep -i 'warning\|error')"

if command -v assimp > /dev/null; then
  for f in deck draco; do
    assimp info "$dir/$f.glb" > "$dir/$f.assimp.txt" 2>&1
    check "assimp reads $f.glb" contains "$dir/$f.assimp.txt" "^Faces: *$faces$"
    check "assimp: $f.glb has the mesh named deck" contains "$dir/$f.assimp.txt" "0 (deck): \[[0-9]* / 0 / $faces "
    # Local coordinates: no UTM-sized numbers anywhere in the placement (the deck is 64 m long).
    check "assimp: $f.glb placed in local coordinates" python3 -c '
import re, sys
t = open(sys.argv[1]).read()
lo = [float(v) for v in re.search(r"Minimum point\s+\(([^)]*)\)", t).group(1).split()]
hi = [float(v) for v in re.search(r"Maximum point\s+\(([^)]*)\)", t).group(1).split()]
assert all(abs(v) < 1000 for v in lo + hi), (lo, hi)' "$dir/$f.assimp.txt"
  done
else
  check "assimp is installed (Debian assimp-utils; tools/build.sh installs it)" false
fi

# Debian's python3-open3d is for Debian's own python3, which may not be the first on PATH.
if /usr/bin/python3 -c "import open3d" 2> /dev/null; then
  check "Open3D reads the plain .glb with colours and normals" /usr/bin/python3 -c '
import sys, open3d as o3d
m = o3d.io.read_triangle_mesh(sys.argv[1])
assert len(m.triangles) == int(sys.argv[2]), (len(m.triangles), sys.argv[2])
assert m.has_vertex_colors() and m.has_vertex_normals()
b = m.get_axis_aligned_bounding_box()
assert max(abs(v) for v in list(b.min_bound) + list(b.max_bound)) < 1000' "$dir/deck.glb" "$faces"
else
  check "Open3D is installed (Debian python3-open3d; tools/build.sh installs it)" false
fi

# A file name that is not UTF-8 (Latin-1 "d\xe9ck"): the .glb's JSON stays valid UTF-8, the name
# read as Latin-1.
cp "$dir/deck.las" "$dir/d"$'\xe9'"ck.las"
"$lasmesh" "$dir/d"$'\xe9'"ck.las" --grid 64 -o "$dir/latin.glb" -q
node "$here/gltf_validate.js" "$validator" "$dir/latin.glb" > "$dir/latin.txt"; rc=$?
check "a Latin-1 input name: the validator finds no error (got: $(head -c 300 "$dir/latin.txt"))" test "$rc" -eq 0
check "a Latin-1 input name: named déck in UTF-8" grep -qa '"name":"déck"' "$dir/latin.glb"

# All or nothing: the second output fails (a file size limit, as a full disk), so the first,
# already written, must not appear either.
"$lasgen" --scene sphere --points 300000 -o "$dir/big.las" > /dev/null
(cd "$dir" && trap '' XFSZ && ulimit -f 8192 && "$lasmesh" big.las --grid 200 --min-piece 0 --simplify 0 --ascii -o small.drc -o big.ply 2> err.txt); rc=$?
check "a failing second output exits 4" test "$rc" -eq 4
check "... and the first output is not left behind" test ! -e "$dir/small.drc" -a ! -e "$dir/big.ply"
check "... nor any temporary file" test -z "$(ls "$dir" | grep '\.tmp$')"

# An empty mesh is an input error (exit 2), writes nothing, and says which option removed what.
"$lasmesh" "$dir/deck.las" --grid 64 --min-piece 1e6 -o "$dir/e.ply" -o "$dir/e.glb" 2> "$dir/err.txt"; rc=$?
check "every piece removed: exit 2" test "$rc" -eq 2
check "... naming --min-piece" contains "$dir/err.txt" "the mesh is empty, nothing written: all [0-9]* pieces ([0-9]* triangles) are smaller than the smallest piece kept, .* (--min-piece)$"
check "... and no output" test ! -e "$dir/e.ply" -a ! -e "$dir/e.glb"
"$lasmesh" "$dir/deck.las" --grid 64 --iso 1e9 -o "$dir/e.ply" 2> "$dir/err.txt"; rc=$?
check "an iso above every cell: exit 2" test "$rc" -eq 2
check "... naming the iso and the fullest cell" contains "$dir/err.txt" "the iso 1e+09 points per cell leaves no cell: the fullest holds [0-9]* points: try an iso below .* (--iso)$"
check "... and no output" test ! -e "$dir/e.ply"

finish "cli viewers"
