#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# End to end: `lasmesh INPUT -o a.ply -o a.drc -o a.glb` in one run. The .drc is decoded by Draco's
# own draco_decoder and checked by the independent PLY reader; the .glb is checked by glb_check.py
# and by the Khronos glTF validator (npm package gltf-validator, installed by tools/test.sh).
# Usage: draco_test.sh LASMESH LASGEN VALIDATOR_FOLDER
set -u
lasmesh=$1 lasgen=$2 validator=$3 here=$(dirname "$0")
source "$(dirname "$0")/common.sh"
ply_count() { sed -n "s/^element $2 //p" "$1" | head -n 1; } # the count of a PLY element
# A copy of a PLY with a `comment origin` line, which ply_check.py needs, after the format line.
with_origin() { python3 -c '
import sys
d = open(sys.argv[1], "rb").read()
i = d.index(b"\n", d.index(b"format")) + 1
open(sys.argv[2], "wb").write(d[:i] + b"comment origin " + sys.argv[3].replace(",", " ").encode() + b"\n" + d[i:])' "$@"; }

# --min-piece 0 keeps the outlier clusters, so the mesh spans the whole cloud for the bounds checks.
"$lasgen" --scene deck --points 300000 -o "$dir/d.las"
# The .glb Draco-compressed with its origin in a translation node: what the checks below expect.
draco_glb="--glb-compression draco --glb-origin node"
# shellcheck disable=SC2086
"$lasmesh" "$dir/d.las" --grid 128 --surface closed --min-piece 0 -o "$dir/a.ply" -o "$dir/a.drc" -o "$dir/a.glb" $draco_glb 2> "$dir/summary.txt"
check "three outputs from one run" test -s "$dir/a.ply" -a -s "$dir/a.drc" -a -s "$dir/a.glb"
check "summary gives the quantization" contains "$dir/summary.txt" "^draco          1[0-6] bits (auto) position quantization, step"
check "summary times each output" contains "$dir/summary.txt" "(ply [0-9.]*, drc [0-9.]*, glb [0-9.]*)"
# Simplified (the default), the faces are uneven and Draco's share of the gain smaller: 7-8 times
# here; the dense mesh of --simplify 0 shrinks more than 20 times.
check "the .drc is much smaller than the PLY" test "$(stat -c %s "$dir/a.drc")" -lt "$(($(stat -c %s "$dir/a.ply") / 5))"
"$lasmesh" "$dir/d.las" --grid 128 --surface closed --min-piece 0 --simplify 0 -o "$dir/dense.ply" -o "$dir/dense.drc" -q
check "--simplify 0: the .drc is a tenth of the PLY at most" test "$(stat -c %s "$dir/dense.drc")" -lt "$(($(stat -c %s "$dir/dense.ply") / 10))"

# The .drc through Draco's own decoder: the same faces and vertices as the PLY, still closed and
# within a cell of the cloud (the origin taken from the .glb's node).
draco_decoder -i "$dir/a.drc" -o "$dir/x.ply" > /dev/null
check "draco_decoder reads the .drc" test -s "$dir/x.ply"
check "decoded .drc has the PLY's faces" test "$(ply_count "$dir/x.ply" face)" = "$(ply_count "$dir/a.ply" face)"
check "decoded .drc has the PLY's vertices" test "$(ply_count "$dir/x.ply" vertex)" = "$(ply_count "$dir/a.ply" vertex)"

# The .glb: container and members, then its Draco bytes through draco_decoder.
read -r origin positions indices < <(python3 "$here/glb_check.py" "$dir/a.glb" "$dir/g.drc")
check "glb_check.py accepts the .glb" test -n "${indices:-}"
check "the node gives the summary's origin" shows_origin "$dir/summary.txt" "$origin"
read -r lo hi < <(bounds "$dir/d.las")
with_origin "$dir/x.ply" "$dir/xo.ply" "$origin"
check "decoded .drc: closed, within a cell of the cloud" python3 "$here/ply_check.py" "$dir/xo.ply" "$lo" "$hi" 0.51
draco_decoder -i "$dir/g.drc" -o "$dir/g.obj" > /dev/null
check "draco_decoder reads the .glb's Draco bytes" test -s "$dir/g.obj"
check "glb POSITION count is the decoded vertex count" test "$(grep -c '^v ' "$dir/g.obj")" = "$positions"
check "glb index count is 3 x the decoded faces" test "$(($(grep -c '^f ' "$dir/g.obj") * 3))" = "$indices"
check "glb has the PLY's faces" test "$((indices / 3))" = "$(ply_count "$dir/a.ply" face)"
check "glb POSITION min and max are the decoded vertices' bounds" python3 "$here/glb_check.py" "$dir/a.glb" "$dir/g2.drc" "$dir/g.obj"

# The Khronos validator: no errors. A copy without the required POSITION bounds must fail it,
# which shows the validator really ran.
node "$here/gltf_validate.js" "$validator" "$dir/a.glb" > "$dir/validator.txt"; rc=$?
cat "$dir/validator.txt"
check "glTF validator: no errors" test "$rc" -eq 0
python3 -c '
import json, struct, sys
d = open(sys.argv[1], "rb").read()
n = struct.unpack_from("<I", d, 12)[0]
g = json.loads(d[20:20 + n])
del g["accessors"][0]["min"]
j = json.dumps(g).encode()
j += b" " * (-len(j) % 4)
rest = d[20 + n:]
open(sys.argv[2], "wb").write(struct.pack("<4sII", b"glTF", 2, 20 + len(j) + len(rest)) + struct.pack("<II", len(j), 0x4E4F534A) + j + rest)' \
  "$dir/a.glb" "$dir/broken.glb"
node "$here/gltf_validate.js" "$validator" "$dir/broken.glb" > "$dir/broken.txt"; rc=$?
check "glTF validator rejects a POSITION without bounds" test "$rc" -eq 1
check "... naming the missing bounds" contains "$dir/broken.txt" "error MESH_PRIMITIVE_POSITION_ACCESSOR_WITHOUT_BOUNDS"

# A cloud without colour (point format 1) gives meshes without colour, still valid.
"$lasgen" --scene sphere --format 1 --points 50000 --origin 500000,6700000,50 -o "$dir/s.las"
# shellcheck disable=SC2086
"$lasmesh" "$dir/s.las" --grid 32 -o "$dir/s.glb" -o "$dir/s.drc" $draco_glb 2> /dev/null
check "colourless .glb passes glb_check.py" python3 "$here/glb_check.py" "$dir/s.glb" "$dir/s_g.drc" > /dev/null
check "colourless .glb has no COLOR_0" test -z "$(grep -a COLOR_0 "$dir/s.glb")"
check "glTF validator: colourless .glb has no errors" node "$here/gltf_validate.js" "$validator" "$dir/s.glb"
draco_decoder -i "$dir/s.drc" -o "$dir/s.ply" > /dev/null
check "colourless .drc decodes without colour" test -z "$(grep -a 'property uchar red' "$dir/s.ply")"

# Same input, same bytes, whatever the threads; the options change the stream.
# shellcheck disable=SC2086
"$lasmesh" "$dir/d.las" --grid 128 --surface closed --min-piece 0 -o "$dir/b.drc" -o "$dir/b.glb" --threads 1 $draco_glb 2> /dev/null
check "the .drc is byte-identical on a second run" cmp -s "$dir/a.drc" "$dir/b.drc"
check "the .glb is byte-identical on a second run" cmp -s "$dir/a.glb" "$dir/b.glb"
"$lasmesh" "$dir/d.las" --grid 128 --surface closed --min-piece 0 -o "$dir/c.drc" --draco-bits 16 --draco-level 0 2> "$dir/summary16.txt"
check "--draco-bits is reported" contains "$dir/summary16.txt" "^draco          16 bits position quantization.*level 0"
check "--draco-bits 16 --draco-level 0 gives other bytes" test "$(stat -c %s "$dir/c.drc")" -gt "$(stat -c %s "$dir/a.drc")"
draco_decoder -i "$dir/c.drc" -o "$dir/c.ply" > /dev/null
check "level 0 (sequential) decodes with the same faces" test "$(ply_count "$dir/c.ply" face)" = "$(ply_count "$dir/a.ply" face)"

# Refusals come before reading: the input named here does not even exist.
"$lasmesh" "$dir/none.las" -o "$dir/x.xyz" 2> "$dir/err.txt"; rc=$?
check "unknown extension is a usage error before reading" test "$rc" -eq 1
check "unknown extension lists the formats" contains "$dir/err.txt" ".ply, .drc, .glb, .png, .html or .json (a tileset)"
"$lasmesh" "$dir/none.las" -o "$dir/no/such/folder/x.drc" 2> "$dir/err.txt"; rc=$?
check "missing folder for a .drc exits 4 before reading" test "$rc" -eq 4
"$lasmesh" "$dir/none.las" -o "$dir/no/such/folder/x.glb" 2> /dev/null; rc=$?
check "missing folder for a .glb exits 4 before reading" test "$rc" -eq 4
for bad in "--draco-bits 0" "--draco-bits 31" "--draco-level 11" "--draco-level -1"; do
  # shellcheck disable=SC2086
  "$lasmesh" "$dir/d.las" -o "$dir/y.drc" $bad 2> /dev/null; rc=$?
  check "$bad is a usage error" test "$rc" -eq 1
done
check "nothing written after a refusal" test ! -e "$dir/y.drc"
check "no temporary file left behind" test -z "$(ls "$dir" | grep '\.tmp$')"

finish "cli draco"
