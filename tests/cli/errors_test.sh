#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Every bad input and environment of issue 7, one row each: the exit code, a phrase of the one-line
# message (the input's name, the byte offset or record where known, what to do), and no file under
# the final output name afterwards. Bad files are a generated LAS with bytes patched.
# Usage: errors_test.sh LASMESH LASGEN
set -u
lasmesh=$(realpath "$1") lasgen=$(realpath "$2")
source "$(dirname "$0")/common.sh"

# expect NAME CODE PHRASE COMMAND...: runs COMMAND (a shell string, so pipes work) with -o out.ply
# appended, and checks the exit code, the phrase in stderr, and that out.ply does not exist.
expect() { expect_exactly "$1" "$2" "$3" "$4 -o out.ply"; }

# expect_exactly NAME CODE PHRASE COMMAND: the same checks, with nothing appended to COMMAND.
expect_exactly() {
  local name=$1 code=$2 phrase=$3 rc
  rm -f "$dir/out.ply"
  (cd "$dir" && eval "$4") > /dev/null 2> "$dir/err.txt"; rc=$?
  check "$name: exit $code (got $rc: $(head -c 300 "$dir/err.txt"))" test "$rc" -eq "$code"
  check "$name: message has \"$phrase\" (got: $(head -c 300 "$dir/err.txt"))" grep -qF -- "$phrase" "$dir/err.txt"
  check "$name: one line" test "$(wc -l < "$dir/err.txt")" -eq 1
  check "$name: no output" test ! -e "$dir/out.ply"
}

# patch SRC DST OFFSET STRUCT VALUE...: DST is SRC with the values packed (Python struct) at OFFSET.
patch() {
  python3 - "$@" <<'EOF'
import struct, sys
src, dst, offset, fmt, *values = sys.argv[1:]
data = bytearray(open(src, "rb").read())
values = [float(v) if "d" in fmt else int(v, 0) for v in values]
struct.pack_into("<" + fmt, data, int(offset), *values)
open(dst, "wb").write(data)
EOF
}

cd "$dir"
"$lasgen" --scene sphere --points 1000 -o ok.las # LAS 1.2, format 3: 34-byte records, one VLR
size=$(stat -c %s ok.las)
patch ok.las signature.las 0 I 0x5853414C # "LASX"
patch ok.las version.las 25 B 5
patch ok.las header-size.las 94 H 100
patch ok.las point-offset.las 96 I 200
patch ok.las record-length.las 105 H 20
patch ok.las format.las 104 B 11
patch ok.las laz.las 104 B 0x83
patch ok.las zero-points.las 107 I 0
patch ok.las more-points.las 107 I 1001
patch ok.las zero-scale.las 131 d 0
patch ok.las nan-scale.las 139 d nan
patch ok.las inf-offset.las 163 d inf
patch ok.las inverted.las 187 d 1e9 # min X above max X
patch ok.las vlr-length.las 247 H 100 # the VLR at 227 now ends past the point data at 312
patch ok.las vlr-count.las 100 I 2
head -c $((size - 34 * 10)) ok.las > truncated.las
head -c $((size - 17)) ok.las > mid-record.las
gzip -c ok.las > ok.las.gz
python3 -c 'import sys; d = bytearray(open("ok.las.gz", "rb").read()); d[len(d) // 2] ^= 0xFF; open("corrupt.las.gz", "wb").write(d)'
head -c 2000 ok.las.gz > truncated.las.gz
zstd -q -c ok.las > ok.las.zst
python3 -c 'import sys; d = bytearray(open("ok.las.zst", "rb").read()); d[len(d) // 2] ^= 0xFF; open("corrupt.las.zst", "wb").write(d)'
mkdir folder

L=\"$lasmesh\"
expect "wrong signature" 2 'signature.las: is not a LAS file: expected the signature "LASF" at byte 0, found "LASX"' "$L signature.las"
expect "unsupported version" 2 'version.las: has LAS version 1.5 (bytes 24-25)' "$L version.las"
expect "header size too small" 2 'header-size.las: header size 100 (byte 94) is smaller than the 227 bytes' "$L header-size.las"
expect "point offset inside header" 2 'point-offset.las: offset to point data 200 (byte 96) lies inside' "$L point-offset.las"
expect "record length below core size" 2 'record-length.las: point record length 20 (byte 105) is shorter than the 34 bytes' "$L record-length.las"
expect "point format 11" 2 'format.las: point data format 11 (byte 104)' "$L format.las"
expect "LAZ bit without LASzip VLR" 2 'laz.las: point format byte 0x83 at byte 104 has the LAZ compression bits set, but there is no LASzip VLR' "$L laz.las"
expect "zero points" 2 'zero-points.las: the header promises no point records' "$L zero-points.las"
expect "more points promised" 2 'more-points.las: ends at byte 34312 after 1000 whole point records, but the header promises 1001' "$L more-points.las"
expect "truncated file" 2 'truncated.las: ends at byte 33972 after 990 whole point records' "$L truncated.las"
expect "mid-record end" 2 'after 999 whole point records and 17 bytes of record 999' "$L mid-record.las"
expect "truncated pipe" 2 'standard input: ends at byte 33972 after 990' "cat truncated.las | $L -"
expect "zero scale" 2 'zero-scale.las: X scale factor at byte 131 is zero' "$L zero-scale.las"
expect "non-finite scale" 2 'nan-scale.las: Y scale factor at byte 139 is not a finite number' "$L nan-scale.las"
expect "non-finite offset" 2 'inf-offset.las: Y offset at byte 163 is not a finite number' "$L inf-offset.las"
expect "min > max bounds" 2 'inverted.las: header bounds are inverted: min X 1e+09 > max 5.001 (bytes 179-226): the header is damaged' "$L inverted.las"
expect "VLR runs past the point data" 2 'vlr-length.las: VLR 0 (user id "lasmesh", record 1, 100 bytes at byte 281) runs past' "$L vlr-length.las"
expect "VLR count too high" 2 'vlr-count.las: VLR 1 of 2 would start at byte 312' "$L vlr-count.las"
expect "corrupt gzip" 2 'corrupt.las.gz: corrupt or truncated gzip stream near compressed byte' "$L corrupt.las.gz"
expect "truncated gzip" 2 'standard input: corrupt or truncated gzip stream' "$L - < truncated.las.gz"
expect "corrupt zstd" 2 'corrupt.las.zst: corrupt or truncated zstd stream' "$L corrupt.las.zst"
expect "empty stdin" 2 'standard input: is empty, expected a LAS file' "$L - < /dev/null"
expect "directory" 2 'folder: is a directory, expected a LAS file' "$L folder"
expect "missing file" 2 'missing.las: cannot open: No such file or directory' "$L missing.las"
expect "unknown output extension" 1 'output "out.obj": unknown extension, expected .ply, .drc, .glb, .png, .html or .json (a tileset) (-o)' "$L ok.las -o out.obj"
# The output folder is checked before the input is opened: a missing input is not reported.
expect "missing output folder" 4 'no/such/x.ply: the folder no/such does not exist' "$L missing.las -o no/such/x.ply"
expect "output folder is a file" 4 'ok.las/x.ply: the folder ok.las does not exist' "$L ok.las -o ok.las/x.ply"
if [ "$(id -u)" -ne 0 ]; then # root may write anywhere
  mkdir locked && chmod 555 locked
  expect "read-only output folder" 4 'locked/x.ply: cannot write in locked: Permission denied' "$L missing.las -o locked/x.ply"
else
  echo "skipped: read-only output folder (running as root)"
fi
# A full disk, as a file size limit: with SIGXFSZ ignored, write(2) fails with EFBIG as it fails
# with ENOSPC on a full disk, through the same checked path. The limit (8 MiB) lets PoCL write its
# kernel cache (it stops with "LLVM ERROR" below about 2 MiB); the ASCII mesh is 26 MB (not
# simplified, with normals).
"$lasgen" --scene sphere --points 300000 -o big.las
expect "disk full while writing" 4 'out.ply: writing failed: File too large: free some space or write elsewhere' \
  "trap '' XFSZ; ulimit -f 8192; $L big.las --grid 200 --min-piece 0 --simplify 0 --ascii"
check "disk full leaves no temporary file" test -z "$(ls -A | grep '\.tmp$')"
expect "grid too large for memory" 1 'cells would fit (--grid ' "$L ok.las --grid 4096 --max-memory 1000"
# A grid asked for is the finest the mesh uses: one far too fine for the points is coarsened, said.
"$lasmesh" ok.las --grid 2048 -o fine.ply 2> err.txt; rc=$?
check "a grid far too fine for the points is coarsened, not refused (exit $rc)" test "$rc" -eq 0 -a -s fine.ply
check "... and the note says so" grep -qF "note: the grid asked for, 2048 x 2048 x 2048 cells, is too fine for these points" err.txt
check "... and the grid line too" grep -qF "(128 times coarser than the 2048 x 2048 x 2048 asked for, too fine)" err.txt
expect "a grid past 16384 cells an axis" 1 '--grid "16385": expected N or NXxNYxNZ with whole numbers from 1 to 16384' "$L ok.las --grid 16385"
expect "a grid of too many bricks" 1 'would hold more than 2147483648 bricks of 4 x 4 x 4 cells; use larger cells, or fewer' "$L ok.las --grid 16384"
expect "over --max-memory" 1 'does not fit' "$L ok.las --grid 2048 --max-memory 64"
expect "no OpenCL platform" 3 'no OpenCL platform found: install one, e.g. `apt-get install pocl-opencl-icd`' \
  "OCL_ICD_VENDORS=$dir/folder $L ok.las"
expect "standard input among several inputs" 1 'standard input (-) must be the only input: with several inputs each is read twice, its header first, and a pipe can be read once' "cat ok.las | $L ok.las -"
expect "a pipe among several inputs" 1 'is a pipe, not a file: with several inputs each is read twice, its header first, and a pipe can be read once; save it to a file, or give it alone' "$L ok.las <(cat ok.las)"
expect "... even with --skip-bad-inputs (a usage error, not a bad file)" 1 'is a pipe, not a file' "$L ok.las <(cat ok.las) --skip-bad-inputs"
"$lasmesh" info ok.las <(cat ok.las) > info.txt; rc=$?
check "lasmesh info reads each header once: both shown (exit $rc)" test "$rc" -eq 0 -a "$(grep -c '^input ' info.txt)" -eq 2
check "... and says the survey cannot be meshed as one, and why" grep -qF 'cannot be meshed as one: /dev/fd/' info.txt
"$lasmesh" <(cat ok.las) -o alone.ply -q; rc=$?
check "a pipe alone is read once, as standard input is (exit $rc)" test "$rc" -eq 0 -a -s alone.ply
expect "--scan-bounds on a pipe" 1 'scanning the bounds reads the input twice, so it needs a regular file, not "-": save the stream to a file, or give the bounds (--scan-bounds)' "cat ok.las | $L - --scan-bounds"
# The kernel build failure (the build log in the message) cannot be caused from the command line:
# tests/accumulate_test.cpp builds a broken kernel through the same function.

# Header bounds that do not contain the points: counted and reported, and --bounds or
# --scan-bounds covers them.
patch ok.las small-bounds.las 179 6d 2.5 -2.5 2.5 -2.5 2.5 -2.5 # the sphere has radius 5
"$lasmesh" small-bounds.las -o small.ply --grid 16 2> err.txt
check "points outside the header bounds are counted" grep -qF "1000 read, 1000 outside the grid" err.txt
check "and the warning says what to do" grep -qF -- "covers them (--scan-bounds or --bounds)" err.txt
"$lasmesh" small-bounds.las -o small.ply --grid 16 --scan-bounds 2> err.txt
check "--scan-bounds covers them" grep -qF "1000 read, 0 outside the grid" err.txt
"$lasmesh" small-bounds.las -o small.ply --grid 16 --bounds=-6,-6,-6,6,6,6 2> err.txt
check "--bounds covers them" grep -qF "1000 read, 0 outside the grid" err.txt
"$lasmesh" grid --scan-bounds --grid 16 --json small-bounds.las > grid.json 2> /dev/null
check "grid --scan-bounds covers them" grep -qF '"points_outside":0' grid.json

# A closed pipe on standard output ends the run with one line and exit code 4, not a crash.
# (A pipe whose reading end is closed before lasmesh starts: no race with the reader.)
rc=$(python3 -c '
import os, subprocess, sys
r, w = os.pipe(); os.close(r)
print(subprocess.run(sys.argv[1:], stdout=w, stderr=open("err.txt", "w")).returncode)' "$lasmesh" info --json ok.las)
check "closed stdout pipe exits 4 (got $rc)" test "$rc" -eq 4
check "closed stdout pipe is named" grep -qF "cannot write to standard output" err.txt

# Issue 19, the second robustness round.
"$lasmesh" ok.las -o m.ply --grid 16 --min-piece 0 -q

# Data loss: an output over the input or over another output is refused before reading.
cp ok.las in.ply
expect "output is the input" 1 'the output "in.ply" and the input "in.ply" are the same file' "$L in.ply -o in.ply"
check "the input is untouched" cmp -s ok.las in.ply
expect "--report over the input" 1 'the report "ok.las" and the input "ok.las" are the same file' "$L ok.las --report ok.las"
check "the input is untouched by --report" cmp -s ok.las in.ply
expect "-o and --report on one path" 1 'the report "./out.ply" and the output "out.ply" are the same file' "$L ok.las --report ./out.ply"
expect_exactly "standard input redirected from the output" 1 '"in.ply" and the input "-" are the same file' "$L - -o in.ply < in.ply"
check "the input read through standard input is untouched" cmp -s ok.las in.ply
cp ok.las piped.ply
"$lasmesh" - -o piped.ply --grid 16 -q < <(cat piped.ply) 2> /dev/null
check "a pipe into standard input is no file to protect: the output is written" test "$(head -c 3 piped.ply)" = ply
ln ok.las hardlink.ply
expect "output is a hard link to the input" 1 'the output "hardlink.ply" and the input "ok.las" are the same file' "$L ok.las -o hardlink.ply"
cp m.ply m-copy.ply
expect_exactly "--heatmap over the cloud" 1 '--heatmap "in.ply" and the input "in.ply" are the same file' "$L compare m.ply in.ply --heatmap in.ply"
expect_exactly "--heatmap over the mesh" 1 '--heatmap "m.ply" and the mesh "m.ply" are the same file' "$L compare m.ply ok.las --heatmap m.ply"
check "the mesh is untouched" cmp -s m.ply m-copy.ply

# Silent wrong results.
python3 -c 'd = bytearray(open("ok.las.gz", "rb").read()); d[-8] ^= 0xFF; open("bad-crc.las.gz", "wb").write(d)'
expect "gzip CRC checked after the last record" 2 'bad-crc.las.gz: corrupt or truncated gzip stream near compressed byte' "$L bad-crc.las.gz"
expect "--voxel 0" 1 '--voxel: expected a positive number, got "0"' "$L ok.las --voxel 0"
expect "--voxel -1" 1 '--voxel: expected a positive number, got "-1"' "$L ok.las --voxel=-1"
expect "--voxel nan" 1 '--voxel: expected a positive number, got "nan"' "$L ok.las --voxel nan"
patch ok.las huge-bounds.las 179 6d 1e300 -1e300 1e300 -1e300 1e300 -1e300
expect "header bounds of 1e300" 2 'huge-bounds.las: header bounds min/max X (bytes 179-194: -1e+300 to 1e+300) lie beyond every coordinate' "$L huge-bounds.las"
patch ok.las huger-bounds.las 179 6d 1e308 -1e308 1e308 -1e308 1e308 -1e308
expect "header bounds of 1e308" 2 'huger-bounds.las: header bounds min/max X (bytes 179-194' "$L huger-bounds.las"
{ cat ok.las; head -c 107 ok.las; } > trailing.las # 3 whole records of 34 bytes and 5 bytes more
"$lasmesh" trailing.las -o trailing.ply --grid 16 2> err.txt; rc=$?
check "records after the header's count: still meshed (got $rc)" test "$rc" -eq 0
check "and counted in a warning" grep -qF 'trailing.las: 107 bytes (3 whole records of 34 bytes) follow the 1000 point records the header counts' err.txt
cat trailing.las | "$lasmesh" info --scan - > /dev/null 2> err.txt
check "a pipe's trailing records are counted while draining" grep -qF 'standard input: 107 bytes (3 whole records' err.txt
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n' > empty.ply
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n' > flat.ply
printf 'ply\nformat ascii 1.0\ncomment origin nan 0 0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' > nan-origin.ply
expect_exactly "compare: an empty mesh" 2 'the mesh has no triangles: nothing to measure' "$L compare empty.ply ok.las"
expect_exactly "compare: zero-area triangles" 2 'every triangle of the mesh has zero area' "$L compare flat.ply ok.las"
expect_exactly "compare: a cloud with no points" 2 'zero-points.las: has no point records: nothing to measure against' "$L compare m.ply zero-points.las"
expect_exactly "compare: comment origin nan" 2 'nan-origin.ply: header line 3 (byte 21): expected "comment origin X Y Z" with three finite numbers' "$L compare nan-origin.ply ok.las"

# Hangs and crashes.
# Offset 1e15 (one ulp: 0.125) and scale 1e-12: every raw value is 1e15 itself, and the cell-start
# search must not walk 2^31 raw values per face (a hang). --bounds: header bounds like these are refused.
patch ok.las far-offset.las 131 6d 1e-12 1e-12 1e-12 1e15 1e15 1e15
timeout 60 "$lasmesh" grid far-offset.las --grid 16 --bounds 1e15,1e15,1e15,1000000000000000.125,1000000000000000.125,1000000000000000.125 > /dev/null 2> err.txt; rc=$?
check "huge offset with one-ulp bounds: no hang (got $rc: $(head -c 200 err.txt))" test "$rc" -eq 0
if command -v script > /dev/null; then
  script -qec "$lasmesh - -o out.ply" /dev/null < /dev/null > tty.txt 2>&1; rc=$?
  check "standard input a terminal: refused (got $rc)" test "$rc" -eq 1
  check "standard input a terminal: says so" grep -qF 'reading a LAS stream from a terminal' tty.txt
fi
expect "SIGXFSZ under ulimit -f" 4 'out.ply: writing failed: File too large' "ulimit -f 8192; $L big.las --grid 200 --min-piece 0 --simplify 0 --ascii"
mkdir home
HOME=$dir/home XDG_CACHE_HOME= POCL_CACHE_DIR= "$lasmesh" ok.las -o cache.ply --grid 16 -q 2> /dev/null
check "PoCL's kernel cache goes to lasmesh's own folder" test -d home/.cache/lasmesh/pocl
check "and not to PoCL's shared one" test ! -e home/.cache/pocl
# A cache folder that cannot be made (.cache is a file here; read-only for a user): a temporary
# one serves the run and goes with it, rather than PoCL finding no platform.
mkdir -p filehome tmp && touch filehome/.cache
HOME=$dir/filehome XDG_CACHE_HOME= POCL_CACHE_DIR= TMPDIR=$dir/tmp "$lasmesh" ok.las -o nocache.ply --grid 16 -q 2> nocache.txt
check "no writable cache folder: meshed all the same (got: $(head -c 200 nocache.txt))" test -s nocache.ply
check "no writable cache folder: its temporary one is gone" test -z "$(ls -A tmp)"
# A file size limit under what the kernel compiler writes: said before anything, exit 4 (LLVM
# would end the run itself with exit 1).
expect "ulimit -f below the kernel compiler's files" 4 'the file size limit (ulimit -f) of 1.0 MiB is below the 4.0 MiB the OpenCL compiler may write' "ulimit -f 1024; $L ok.las"

# Memory bounded by options, not by input fields.
python3 - <<'PY'
d = bytearray(open("ok.las", "rb").read()[:312])
d[105:107] = (65535).to_bytes(2, "little"); d[107:111] = (10).to_bytes(4, "little")
open("long-records.las", "wb").write(d + bytes(10 * 65535))
PY
# Address-space limits (ulimit -v) cannot hold a binary built with AddressSanitizer, which
# reserves terabytes of address space up front: tools/test.sh sets LASMESH_SANITIZED for that run.
if [ -n "${LASMESH_SANITIZED:-}" ]; then
  echo "skipped: memory limits under ulimit -v (AddressSanitizer build)"
else
(ulimit -v 1500000; "$lasmesh" info --scan long-records.las > /dev/null 2> err.txt); rc=$?
check "info --scan of 65,535-byte records in 1.5 GB (got $rc: $(head -c 200 err.txt))" test "$rc" -eq 0
(ulimit -v 1500000; "$lasmesh" info --scan --chunk-points 1073741824 ok.las > /dev/null 2> err.txt); rc=$?
check "info --scan --chunk-points 2^30 in 1.5 GB (got $rc: $(head -c 200 err.txt))" test "$rc" -eq 0
# A grid the system has no memory for: exit 5, one line with what to change, nothing written.
expect "grid beyond the process's memory" 5 'out of memory: the system refused more (a smaller --grid' \
  "ulimit -v 1000000; $L big.las --grid 3000"
patch ok.las huge-count.las 107 I 0xFFFFFFFF
expect_exactly "compare --samples 2^34 with a lying count" 2 'huge-count.las: ends at byte 34312 after 1000 whole point records' \
  "ulimit -v 3000000; $L compare m.ply huge-count.las --samples 17179869184"
fi
expect_exactly "compare --mesh-samples too many" 1 '--mesh-samples' "$L compare m.ply ok.las --mesh-samples 4294967296"
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 4294967295\nproperty float x\nproperty float y\nproperty float z\nend_header\n' > many.ply
expect_exactly "PLY declaring 2^32-1 vertices in a tiny file" 2 'many.ply: byte 124: the PLY header declares elements that need at least 4294967295 bytes, but only 0 follow it' "$L compare many.ply ok.las"

expect "--draco-bits 28: refused, not 1 GB" 1 '--draco-bits: expected 1 to 24 bits, got "28"' "$L ok.las -o out.drc --draco-bits 28"
check "--draco-bits 28: no .drc" test ! -e out.drc

# Exit codes and messages.
expect "--device with 20 digits" 1 'device 99999999999999999999: there are 1 devices (--device' "$L ok.las --device 99999999999999999999"
mkdir folder.ply
expect_exactly "compare on a directory" 2 'folder.ply: is a directory, expected a mesh file' "$L compare folder.ply ok.las"
"$lasgen" --scene sphere --points 1000 --las-version 1.4 -o v14.las
patch v14.las v14-count.las 247 Q 0
patch v14-count.las v14-count.las 107 I 20000
expect "LAS 1.4 count 0, legacy count not" 2 'its 64-bit point count (bytes 247-254) is 0 but its legacy point count (bytes 107-110) is 20000' "$L v14-count.las"
expect_exactly "LAS 1.4 count 0, legacy count not: info says so too" 2 'v14-count.las: its 64-bit point count (bytes 247-254) is 0 but its legacy point count (bytes 107-110) is 20000: the header is inconsistent' "$L info v14-count.las"
expect_exactly "LAS 1.4 count 0, legacy count not: and grid" 2 'the header is inconsistent' "$L grid v14-count.las"

# Option values in our own words (what was expected, what was given), not the parser's.
expect "--surface bogus" 1 '--surface: expected sheet or closed, got "bogus"' "$L ok.las --surface bogus"
expect "--surface 1 is no surface" 1 '--surface: expected sheet or closed, got "1"' "$L ok.las --surface 1"
expect "--threads abc" 1 '--threads: expected a whole number from 1 to 1024, got "abc"' "$L ok.las --threads abc"
expect "--draco-level 11" 1 '--draco-level: expected a whole number from 0 to 10, got "11"' "$L ok.las --draco-level 11"
expect "--voxel abc" 1 '--voxel: expected a positive number, got "abc"' "$L ok.las --voxel abc"
expect "--placement iso with the sheet" 1 'vertices on the iso level are for the closed surface only' "$L ok.las --placement iso"
head -c 2000 ok.las.zst > truncated.las.zst
expect "truncated zstd" 2 'truncated.las.zst: corrupt or truncated zstd stream' "$L truncated.las.zst"
bzip2 -c ok.las > ok.las.bz2
python3 -c 'd = bytearray(open("ok.las.bz2", "rb").read()); d[20] ^= 0xFF; open("corrupt.las.bz2", "wb").write(d)'
expect "corrupt bzip2" 2 'corrupt.las.bz2: corrupt or truncated bzip2 stream' "$L corrupt.las.bz2"
expect "--voxel 1e-300: short numbers" 1 'the grid would need 1e+301 cells along one axis, more than 16384' "$L ok.las --voxel 1e-300"
check "--voxel 1e-300: no 300-digit number" test "$(wc -c < err.txt)" -lt 200
expect "--chunk-mb 0" 1 'expected a positive number, got "0"' "$L ok.las --chunk-mb 0"
check "--chunk-mb 0: no DBL_MAX" test -z "$(grep -F 'e+308' err.txt)"
expect "unknown option: one line with the prefix" 1 'lasmesh: The following argument was not expected: --bogus' "$L ok.las --bogus"
python3 -c 'd = bytearray(open("ok.las", "rb").read()); d[26:36] = b"\x1b]0;pwn\x07\x1b[2J"[:10]; open("escape.las", "wb").write(d)'
"$lasmesh" info escape.las > info.txt
check "header strings: escape sequences escaped" grep -qF 'system identifier    \x1b]0;pwn\x07\x1b' info.txt
check "header strings: no raw escape byte" test -z "$(grep -P '\x1b' info.txt)"

# Temporary files: a short name of their own, so a legal long output name works.
long=$(printf 'a%.0s' $(seq 248)).ply
"$lasmesh" ok.las -o "$long" --grid 16 -q; rc=$?
check "a 252-character output name (got $rc)" test "$rc" -eq 0 -a -s "$long"

finish "cli errors"
