#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Reader benchmark: `lasmesh info --scan` against `cat FILE > /dev/null` on the same generated
# file (about 1 GB, in the page cache), best of 3 runs each.
# Usage: tools/bench_reader.sh [POINTS] [FILE]   (defaults: 31,000,000 points, out/bench-31M.las)
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-31000000}
file=${2:-out/bench-${points}.las}
mkdir -p "$(dirname "$file")"
[ -f "$file" ] || build/lasgen --scene deck --points "$points" -o "$file"
bytes=$(stat -c %s "$file")
cat "$file" > /dev/null # warm the page cache

source tools/bench_common.sh
t_cat=$(best cat "$file")
t_scan=$(best build/lasmesh info --scan "$file")
mb=$(echo "$bytes / 1000000" | bc -l)
printf 'file          %s (%d points, %.0f MB)\n' "$file" "$points" "$mb"
printf 'cat           %.3f s  %.0f MB/s\n' "$t_cat" "$(echo "$mb / $t_cat" | bc -l)"
printf 'info --scan   %.3f s  %.0f MB/s  %.1f M points/s\n' "$t_scan" "$(echo "$mb / $t_scan" | bc -l)" \
  "$(echo "$points / $t_scan / 1000000" | bc -l)"
printf 'reader / cat  %.2f of cat'"'"'s rate\n' "$(echo "$t_cat / $t_scan" | bc -l)"
