#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Sparse grid: memory and time from grid 256 to 4096 on a deck scan, to show they grow with the
# scanned surface (about x4 a doubling), not the volume (x8). One run each, one Markdown table.
# Usage: bash tools/bench_sparse.sh [POINTS] [GRIDS...]   (defaults: 50,000,000  256 512 1024 2048 4096)
# Needs about 1.7 GB of disk in out/bench/ for the 50M scene.
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-50000000}
shift || true
grids=("${@:-256 512 1024 2048 4096}")
read -r -a grids <<< "${grids[*]}"
source tools/bench_common.sh
mkdir -p out/bench
file=out/bench/deck-$points-scan.las
[ -s "$file" ] || build/lasgen --scene deck --points "$points" --order scan -o "$file"
t_cat=$(best cat "$file")
echo "machine: $(nproc) cores; device: $(build/lasmesh devices | head -1 | xargs); cat $(printf %.2f "$t_cat") s for $(( $(stat -c %s "$file") / 1000000 )) MB"
echo
echo "| grid | cell m | occupied cells | bricks | grid MB device / host | read+acc s | extract s | total s | total/cat | peak RSS MB | triangles | DRC MB |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for grid in "${grids[@]}"; do
  base=out/bench/sparse-$points-$grid
  build/lasmesh "$file" --grid "$grid" -o "$base.drc" --report "$base.json" -q
  python3 - "$base.json" "$t_cat" <<'PY'
import json, sys
r, cat = json.load(open(sys.argv[1])), float(sys.argv[2])
s, g = r["seconds"], r["sparse_grid"]
print(f"| {r['grid']['dims'][0]} | {r['grid']['cell_size']:.4f} | {g['occupied_cells']} | {g['occupied_bricks']} | "
      f"{g['pool_bytes'] / 1e6:.0f} / {g['host_grid_bytes'] / 1e6:.0f} | {s['read_accumulate']:.2f} | {s['extract']:.2f} | {s['total']:.2f} | "
      f"{s['total'] / cat:.1f} | {r['peak_rss_bytes'] / 1e6:.0f} | {r['triangles']} | {r['outputs'][0]['bytes'] / 1e6:.2f} |")
PY
done
