#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The benchmark suite: generated deck scenes of 1M, 10M and 50M points, meshed at grids 128,
# 256 and 512 into PLY, DRC and GLB in one run each, with the time per stage, peak memory,
# output sizes, fidelity (lasmesh compare) and the ratio to `cat FILE > /dev/null` measured on
# the same file in the same run. Prints one Markdown table.
# Usage: bash tools/bench.sh [POINTS...]   (default: 1000000 10000000 50000000)
# Needs about 2 GB of disk in out/bench/ for the 50M scene.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh > /dev/null
source tools/bench_common.sh
sizes=("${@:-1000000 10000000 50000000}")
read -r -a sizes <<< "${sizes[*]}"
mkdir -p out/bench
echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GB", $2 / 1048576}' /proc/meminfo),"\
     "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); device: $(./build/lasmesh devices | head -1 | xargs)"
echo
echo "| points | input MB | grid | read+acc s | extract s | write s | total s | cat s | total/cat | M points/s | peak RSS MB | PLY MB | DRC MB | GLB MB | c2m mean | c2m p95 | cell |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for n in "${sizes[@]}"; do
  las=out/bench/deck-$n.las
  [ -s "$las" ] || ./build/lasgen --scene deck --points "$n" -o "$las"
  cat_s=$(best cat "$las")
  for grid in 128 256 512; do
    base=out/bench/deck-$n-$grid
    ./build/lasmesh "$las" --grid "$grid" -o "$base.ply" -o "$base.drc" -o "$base.glb" --report "$base.json" -q
    ./build/lasmesh compare "$base.ply" "$las" --samples 2000000 --mesh-samples 500000 --json > "$base.compare.json"
    python3 - "$n" "$las" "$base.json" "$base.compare.json" "$cat_s" <<'PY'
import json, os, sys
n, las, report, compare, cat_s = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4], float(sys.argv[5])
r, c = json.load(open(report)), json.load(open(compare))
s = r["seconds"]
size = {os.path.splitext(o["path"])[1]: o["bytes"] / 1e6 for o in r["outputs"]}
mb = os.path.getsize(las) / 1e6
print(f"| {n / 1e6:g}M | {mb:.0f} | {r['grid']['dims'][0]}x{r['grid']['dims'][1]}x{r['grid']['dims'][2]} | "
      f"{s['read_accumulate']:.2f} | {s['extract']:.2f} | {s['write']:.2f} | {s['total']:.2f} | {cat_s:.2f} | "
      f"{s['total'] / cat_s:.1f} | {n / s['total'] / 1e6:.1f} | {r['peak_rss_bytes'] / 1e6:.0f} | "
      f"{size['.ply']:.2f} | {size['.drc']:.3f} | {size['.glb']:.3f} | "
      f"{c['cloud_to_mesh']['mean']:.3f} | {c['cloud_to_mesh']['p95']:.3f} | {r['grid']['cell_size']:.3f} |")
PY
  done
done
