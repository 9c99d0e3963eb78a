#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Faults during a run: kill -9 at random moments never leaves an incomplete file under a final
# name; SIGINT and SIGTERM remove the temporary files and exit 130 and 143.
# Usage: signals_test.sh LASMESH LASGEN [ITERATIONS]
set -u
lasmesh=$(realpath "$1") lasgen=$(realpath "$2") iterations=${3:-20}
source "$(dirname "$0")/common.sh"
cd "$dir"

# A binary PLY is complete when its size is exactly the header plus every element it declares.
ply_complete() { python3 - "$1" <<'EOF'
import struct, sys
data = open(sys.argv[1], "rb").read()
end = data.index(b"end_header\n") + len(b"end_header\n")
lines = data[:end].decode().splitlines()
assert lines[0] == "ply" and lines[1] == "format binary_little_endian 1.0", lines[:2]
vertices = int(next(l for l in lines if l.startswith("element vertex")).split()[2])
faces = int(next(l for l in lines if l.startswith("element face")).split()[2])
vertex_size = 12 + (12 if "property float nx" in lines else 0) + (3 if "property uchar red" in lines else 0)
at = end + vertices * vertex_size
for _ in range(faces):  # each face: a uchar count, then that many int32 indices
    at += 1 + 4 * data[at]
assert at == len(data), f"{sys.argv[1]}: {len(data)} bytes, the header declares {at}"
EOF
}
final_files_complete() {
  local ok=0
  if [ -e out.ply ]; then ply_complete out.ply || ok=1; fi
  if [ -e out.drc ]; then draco_decoder -i out.drc -o decoded.ply > /dev/null || ok=1; fi
  return $ok
}

"$lasgen" --scene sphere --points 300000 -o s.las
run=("$lasmesh" s.las -o out.ply -o out.drc --grid 160) # not a function: $! must be lasmesh itself

# One whole run: how long it takes, and that the checks accept its outputs.
start=$(date +%s%N)
"${run[@]}" 2> /dev/null
full_ns=$(($(date +%s%N) - start))
echo "a whole run: $((full_ns / 1000000)) ms"
check "a whole run's outputs pass the completeness checks" final_files_complete
check "and both exist" test -e out.ply -a -e out.drc
rm -f out.ply out.drc
# The checks themselves can fail: a PLY or a Draco file cut short is refused.
fails() { ! "$@" > /dev/null 2>&1; }
"$lasmesh" s.las -o cut.ply -o cut.drc --grid 32 2> /dev/null
head -c -5 cut.ply > short.ply
head -c -5 cut.drc > short.drc
check "a PLY cut short fails the check" fails ply_complete short.ply
check "a Draco file cut short fails the check" fails draco_decoder -i short.drc -o decoded.ply

# kill -9 after a random delay from 0 to 110% of a whole run.
complete=0 killed=0 finished=0
for ((i = 0; i < iterations; i++)); do
  rm -f out.ply out.drc
  delay_ms=$((RANDOM % (full_ns / 1000000 * 11 / 10 + 1)))
  "${run[@]}" 2> /dev/null &
  pid=$!
  sleep "$((delay_ms / 1000)).$(printf %03d $((delay_ms % 1000)))"
  if kill -9 "$pid" 2> /dev/null; then killed=$((killed + 1)); else finished=$((finished + 1)); fi
  wait "$pid" 2> /dev/null
  if final_files_complete; then complete=$((complete + 1)); else echo "after kill -9 at ${delay_ms} ms: incomplete"; fi
  rm -f .lasmesh-*.tmp # kill -9 may leave these; never under the final name
done
check "kill -9 at $iterations random moments: every final file complete ($complete; $killed killed, $finished finished)" \
  test "$complete" -eq "$iterations"

# SIGINT while reading: the input arrives slowly through a pipe; exit 130, nothing left behind.
# Job control on: a script's background jobs otherwise start with SIGINT ignored, and lasmesh
# respects an ignored signal (as under nohup).
rm -f out.ply
set -m
{ head -c 1000000 s.las; sleep 3; tail -c +1000001 s.las; } | "$lasmesh" - -o out.ply 2> err.txt &
pid=$!
sleep 1
# On a slow machine lasmesh may not have started yet: wait until it blocks SIGINT (its signal
# thread takes it from there), as its status in /proc shows.
for _ in $(seq 600); do
  blocked=$(awk '/^SigBlk/ {print $2}' "/proc/$pid/status" 2> /dev/null)
  [[ -n $blocked ]] && (( 0x$blocked & 2 )) && break
  sleep 0.05
done
kill -INT "$pid"
wait "$pid"; rc=$?
check "SIGINT exits 130 (got $rc)" test "$rc" -eq 130
check "SIGINT says so" grep -qF "lasmesh: stopped by SIGINT; unfinished outputs removed" err.txt
check "SIGINT leaves no output" test ! -e out.ply
check "SIGINT leaves no temporary file" test -z "$(compgen -G '.lasmesh-*.tmp')"
set +m

# SIGTERM while writing: sent as soon as the temporary file appears (a 26 MB ASCII PLY takes a
# while to write); retried when the run wins the race. On a busy machine the signal can also
# come after the output was finished and renamed, before the exit: then the file under the final
# name must be the whole output (the same bytes as an undisturbed run).
write=("$lasmesh" s.las --grid 200 --min-piece 0 --ascii)
"${write[@]}" -o whole.ply 2> /dev/null
caught=0 late_whole=1
for ((attempt = 0; attempt < 5 && caught == 0; attempt++)); do
  rm -f out.ply
  "${write[@]}" -o out.ply 2> err.txt &
  pid=$!
  until compgen -G '.lasmesh-*.tmp' > /dev/null || ! kill -0 "$pid" 2> /dev/null; do :; done
  kill -TERM "$pid" 2> /dev/null
  wait "$pid"; rc=$?
  if [ -e out.ply ]; then
    cmp -s out.ply whole.ply || late_whole=0
  elif [ "$rc" -eq 143 ]; then
    caught=1
  fi
done
check "SIGTERM while writing exits 143 (got $rc)" test "$rc" -eq 143
check "SIGTERM while writing leaves no output" test ! -e out.ply
check "an output finished before a late SIGTERM is whole" test "$late_whole" -eq 1
check "SIGTERM while writing removes the temporary file" test -z "$(compgen -G '.lasmesh-*.tmp')"

finish "cli signals"
