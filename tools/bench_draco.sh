#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Output benchmark: sizes and encode times of PLY (binary), Draco (.drc) and glTF (.glb) for the
# generated deck at several grids, all three written by one `lasmesh` run. Times are the per-output
# seconds of the summary, best of 3 runs.
# Usage: tools/bench_draco.sh [POINTS] [GRIDS...]   (defaults: 2,000,000  128 256 512)
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-2000000}
[ $# -eq 0 ] || shift
grids=("$@")
[ $# -gt 0 ] || grids=(128 256 512)
file=out/bench-${points}.las
mkdir -p out
[ -f "$file" ] || build/lasgen --scene deck --points "$points" -o "$file"
las_bytes=$(stat -c %s "$file")
printf 'input: %s, %d points, %d bytes\n\n' "$file" "$points" "$las_bytes"
printf '| grid | triangles | bits (step) | PLY bytes | DRC bytes | GLB bytes | LAS/PLY | LAS/DRC | LAS/GLB | PLY/DRC | ply s | drc s | glb s |\n'
printf '|---|---|---|---|---|---|---|---|---|---|---|---|---|\n'
for grid in "${grids[@]}"; do
  best_ply=999 best_drc=999 best_glb=999
  for _ in 1 2 3; do
    build/lasmesh "$file" --grid "$grid" -o out/bench.ply -o out/bench.drc -o out/bench.glb 2> out/bench-summary.txt
    read -r t_ply t_drc t_glb < <(sed -n 's/.*(ply \([0-9.]*\), drc \([0-9.]*\), glb \([0-9.]*\)).*/\1 \2 \3/p' out/bench-summary.txt)
    best_ply=$(echo "if ($t_ply < $best_ply) $t_ply else $best_ply" | bc -l)
    best_drc=$(echo "if ($t_drc < $best_drc) $t_drc else $best_drc" | bc -l)
    best_glb=$(echo "if ($t_glb < $best_glb) $t_glb else $best_glb" | bc -l)
  done
  triangles=$(sed -n 's/^mesh .*vertices, \([0-9]*\) triangles.*/\1/p' out/bench-summary.txt)
  quantization=$(sed -n 's/^draco *\([0-9]*\) bits.*step \([0-9.e-]*\).*/\1 (\2)/p' out/bench-summary.txt)
  ply=$(stat -c %s out/bench.ply) drc=$(stat -c %s out/bench.drc) glb=$(stat -c %s out/bench.glb)
  printf '| %s | %s | %s | %s | %s | %s | %.0f | %.0f | %.0f | %.1f | %.3f | %.3f | %.3f |\n' "$grid" "$triangles" "$quantization" \
    "$ply" "$drc" "$glb" "$(echo "$las_bytes / $ply" | bc -l)" "$(echo "$las_bytes / $drc" | bc -l)" \
    "$(echo "$las_bytes / $glb" | bc -l)" "$(echo "$ply / $drc" | bc -l)" "$best_ply" "$best_drc" "$best_glb"
done
