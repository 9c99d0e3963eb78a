#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Extraction and end-to-end benchmark: `lasmesh INPUT -o OUT.ply` on a generated deck scene with
# 1 and 2 threads at grids 256 and 512, and the whole run against `cat FILE > /dev/null`.
# Usage: tools/bench_extract.sh [POINTS]   (default 20,000,000)
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-20000000}
file=out/bench-${points}.las
mkdir -p out
[ -f "$file" ] || build/lasgen --scene deck --points "$points" -o "$file"
cat "$file" > /dev/null
start=$(date +%s.%N); cat "$file" > /dev/null; end=$(date +%s.%N)
printf 'cat: %.3f s for %d points\n' "$(echo "$end - $start" | bc -l)" "$points"
for grid in 256 512; do
  for threads in 1 2; do
    echo "--grid $grid --threads $threads"
    build/lasmesh "$file" -o out/bench.ply --grid "$grid" --threads "$threads" 2>&1 | grep -E "^(grid|mesh|seconds)"
  done
done
