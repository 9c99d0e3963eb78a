#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Read + accumulate speed against `cat FILE > /dev/null`, on a deck scan in acquisition-like
# order (consecutive points close together) and in random order, page cache warm, best of 3,
# all in the same run: `lasmesh info --scan`, `lasmesh grid` (read + accumulate) and the whole
# run to PLY. Prints one Markdown table.
# Usage: bash tools/bench_speed.sh [POINTS] [GRID] [DEVICE]   (defaults: 20,000,000  256  auto)
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-20000000}
grid=${2:-256}
device=${3:-auto}
source tools/bench_common.sh
mkdir -p out/bench
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); device: $(build/lasmesh devices | head -1 | xargs)"
echo
echo "| order | points | MB | cat s | info --scan s (x cat) | read+accumulate s (x cat) | whole run s (x cat) | extract s |"
echo "|---|---|---|---|---|---|---|---|"
for order in scan random; do
  file=out/bench/deck-$points-$order.las
  [ -s "$file" ] || build/lasgen --scene deck --points "$points" --order "$order" -o "$file"
  cat "$file" > /dev/null
  build/lasmesh grid --grid "$grid" --device "$device" "$file" > /dev/null # warm the kernel cache
  t_cat=$(best cat "$file")
  t_scan=$(best build/lasmesh info --scan "$file")
  t_grid=$(best build/lasmesh grid --grid "$grid" --device "$device" "$file")
  t_run=$(best build/lasmesh "$file" --grid "$grid" --device "$device" -o out/bench/speed.ply -q)
  build/lasmesh "$file" --grid "$grid" --device "$device" -o out/bench/speed.ply -q --report out/bench/speed.json
  extract=$(python3 -c "import json; print('%.2f' % json.load(open('out/bench/speed.json'))['seconds']['extract'])")
  printf '| %s | %d | %d | %.3f | %.3f (%.1f) | %.3f (%.1f) | %.3f (%.1f) | %s |\n' "$order" "$points" \
    "$(( $(stat -c %s "$file") / 1000000 ))" "$t_cat" "$t_scan" "$(echo "$t_scan / $t_cat" | bc -l)" \
    "$t_grid" "$(echo "$t_grid / $t_cat" | bc -l)" "$t_run" "$(echo "$t_run / $t_cat" | bc -l)" "$extract"
done
