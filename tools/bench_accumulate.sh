#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Accumulation benchmark: `lasmesh grid` (read + accumulate on the OpenCL device) against
# `cat FILE > /dev/null` on the same generated file in the page cache, best of 3 runs each.
# Usage: tools/bench_accumulate.sh [POINTS] [GRID] [DEVICE]   (defaults: 31,000,000  256  auto)
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-31000000}
grid=${2:-256}
device=${3:-auto}
file=out/bench-${points}.las
mkdir -p out
[ -f "$file" ] || build/lasgen --scene deck --points "$points" -o "$file"
cat "$file" > /dev/null
build/lasmesh grid --grid "$grid" --device "$device" "$file" > /dev/null # warm the kernel cache

source tools/bench_common.sh
t_cat=$(best cat "$file")
t_grid=$(best build/lasmesh grid --grid "$grid" --device "$device" "$file")
build/lasmesh grid --grid "$grid" --device "$device" "$file" | sed -n '1,2p'
printf 'points        %d (%s MB)\n' "$points" "$(( $(stat -c %s "$file") / 1000000 ))"
printf 'cat           %.3f s\n' "$t_cat"
printf 'lasmesh grid  %.3f s  %.1f M points/s  (%.1f x cat)\n' "$t_grid" \
  "$(echo "$points / $t_grid / 1000000" | bc -l)" "$(echo "$t_grid / $t_cat" | bc -l)"
