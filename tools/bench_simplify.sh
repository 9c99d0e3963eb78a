#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Simplification benchmark (issue 17) on today's default extraction (--surface sheet). For each
# grid and --simplify bound: the triangles, the .drc size and the cloud-to-mesh error of the
# pipeline's output (`lasmesh compare --json`: median, mean of the points within 2 cells, p95, in
# cells), then the simplification alone on the unsimplified mesh with tools/simplify_bench (best
# of 3 runs: wall and CPU seconds, triangles in per wall second; faces turned over against the
# original surface, new non-manifold edges, faces without area, and the largest sampled distance
# between the two surfaces, in cells).
# Usage: tools/bench_simplify.sh [POINTS] [GRIDS...]   (defaults: 5,000,000  512 1024)
# SIMPLIFY_BOUNDS="0 0.25 0.5 1" (in cells) and SIMPLIFY_THREADS (default: all cores) narrow it.
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-5000000}
[ $# -eq 0 ] || shift
grids=("$@")
[ $# -gt 0 ] || grids=(512 1024)
bounds=(${SIMPLIFY_BOUNDS:-0 0.25 0.5 1})
threads=${SIMPLIFY_THREADS:-0}
file=out/deck-${points}.las
mkdir -p out
[ -f "$file" ] || build/lasgen --scene deck --points "$points" -o "$file" > /dev/null
printf 'input: %s, %d points\n\n' "$file" "$points"
printf '| grid | --simplify | triangles | DRC bytes | median | mean within 2 cells | p95 | wall s | CPU s | triangles/s | turned over | new non-manifold edges | no area | largest distance |\n'
printf '|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n'
for grid in "${grids[@]}"; do
  build/lasmesh "$file" --grid "$grid" --simplify 0 -o out/bs-base.ply -q
  for bound in "${bounds[@]}"; do
    build/lasmesh "$file" --grid "$grid" --simplify "${bound}cell" -o out/bs.drc --report out/bs.json -q
    build/lasmesh compare out/bs.drc "$file" --json > out/bs-compare.json
    if [ "$bound" != 0 ]; then
      build/simplify_bench out/bs-base.ply "$bound" --runs 3 --threads "$threads" > out/bs-bench.json
    else
      echo '{}' > out/bs-bench.json
    fi
    python3 - "$grid" "$bound" out/bs.json out/bs-compare.json "$(stat -c %s out/bs.drc)" out/bs-bench.json <<'PY'
import json, sys
grid, bound, report, compare, drc, bench = sys.argv[1], sys.argv[2], json.load(open(sys.argv[3])), json.load(open(sys.argv[4])), sys.argv[5], json.load(open(sys.argv[6]))
cell = report["grid"]["cell_size"]
c = compare["cloud_to_mesh"]
b = bench
if b:
    speed = f"{b['seconds']:.2f} | {b['cpu_seconds']:.2f} | {b['triangles_per_second'] / 1e6:.2f} M"
    checks = f"{b['flipped']} | {b['new_bad_edges']} | {b['zero_area']} | {max(b['simplified_to_original_max'], b['original_to_simplified_max']):.2f}"
else:
    speed, checks = "- | - | -", "- | - | - | -"
print(f"| {grid} | {bound}cell | {report['triangles']} | {drc} | {c['median'] / cell:.3f} | {c['mean_within_2_cells'] / cell:.3f} | "
      f"{c['p95'] / cell:.3f} | {speed} | {checks} |")
PY
  done
done
