#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Accuracy below the cell: the one-sheet surface against the closed one, on the deck with and
# without noise, measured both ways by `lasmesh compare` (every point), distances in cells.
# Usage: bash tools/bench_accuracy.sh [POINTS] [GRIDS...]   (defaults: 5,000,000  256 1024 2048)
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-5000000}
shift || true
grids=("${@:-256 1024 2048}")
read -r -a grids <<< "${grids[*]}"
mkdir -p out/bench
echo "| noise | grid | surface | triangles | c2m mean | c2m mean within 2 cells | c2m median | c2m p95 | within 1 / 2 cells | m2c mean | m2c p95 | DRC kB | extract s |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for noise in 0.01 0; do
  las=out/bench/deck-$points-noise$noise.las
  [ -s "$las" ] || build/lasgen --scene deck --points "$points" --noise "$noise" -o "$las"
  for grid in "${grids[@]}"; do
    for surface in closed sheet; do
      base=out/bench/acc-$points-$noise-$grid-$surface
      build/lasmesh "$las" --grid "$grid" --surface "$surface" -o "$base.ply" -o "$base.drc" --report "$base.json" -q
      build/lasmesh compare "$base.ply" "$las" --json > "$base.compare.json"
      python3 - "$noise" "$base.json" "$base.compare.json" "$surface" <<'PY'
import json, sys
noise, r, c, surface = sys.argv[1], json.load(open(sys.argv[2])), json.load(open(sys.argv[3])), sys.argv[4]
h = c["cell_size"]
a, b = c["cloud_to_mesh"], c["mesh_to_cloud"]
drc = [o["bytes"] for o in r["outputs"] if o["path"].endswith(".drc")][0]
print(f"| {noise} | {r['grid']['dims'][0]} | {surface} | {r['triangles']} | {a['mean'] / h:.3f} | {a['mean_within_2_cells'] / h:.3f} | "
      f"{a['median'] / h:.3f} | {a['p95'] / h:.3f} | {100 * a['within_1_cell']:.2f}% / {100 * a['within_2_cells']:.2f}% | "
      f"{b['mean'] / h:.3f} | {b['p95'] / h:.3f} | {drc / 1e3:.0f} | {r['seconds']['extract']:.2f} |")
PY
    done
  done
done
