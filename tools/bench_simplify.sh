#!/usr/bin/env bash
# Simplification benchmark (issue 17): for each grid and --simplify bound, the triangles, the .drc
# size, the cloud-to-mesh error (`lasmesh compare --json`: mean and p95, in cells) and the
# simplification time from --report. Measured with today's marching-cubes extraction.
# Usage: tools/bench_simplify.sh [POINTS] [GRIDS...]   (defaults: 5,000,000  256 512 1024)
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-5000000}
[ $# -eq 0 ] || shift
grids=("$@")
[ $# -gt 0 ] || grids=(256 512 1024)
file=out/deck-${points}.las
mkdir -p out
[ -f "$file" ] || build/lasgen --scene deck --points "$points" -o "$file" > /dev/null
printf 'input: %s, %d points\n\n' "$file" "$points"
printf '| grid | --simplify | triangles | DRC bytes | mean (cells) | p95 (cells) | simplify s | triangles/s |\n'
printf '|---|---|---|---|---|---|---|---|\n'
for grid in "${grids[@]}"; do
  for bound in 0 0.25cell 0.5cell 1cell; do
    build/lasmesh "$file" --grid "$grid" --simplify "$bound" -o out/bs.drc --report out/bs.json -q
    build/lasmesh compare out/bs.drc "$file" --json > out/bs-compare.json
    python3 - "$grid" "$bound" out/bs.json out/bs-compare.json "$(stat -c %s out/bs.drc)" <<'PY'
import json, sys
grid, bound, report, compare, drc = sys.argv[1], sys.argv[2], json.load(open(sys.argv[3])), json.load(open(sys.argv[4])), sys.argv[5]
cell = report["grid"]["cell_size"]
s = report["simplify"]
c = compare["cloud_to_mesh"]
rate = f"{s['triangles_before'] / s['seconds'] / 1e6:.1f} M" if s["seconds"] > 0 else "-"
print(f"| {grid} | {bound} | {report['triangles']} | {drc} | {c['mean'] / cell:.3f} | {c['p95'] / cell:.3f} | {s['seconds']:.2f} | {rate} |")
PY
  done
done
