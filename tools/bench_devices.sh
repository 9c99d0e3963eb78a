#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Every OpenCL device of this machine on the same deck, in the same run: read + accumulate
# (`lasmesh grid --grid 1024`, best of 3), the whole default run (wall, CPU, peak memory) and the
# outputs' SHA-256, which must be the same on every device. `cat FILE > /dev/null` is the yardstick.
# Usage: tools/bench_devices.sh [POINTS]   (default 50,000,000; the file is about 34 bytes a point)
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-50000000}
file=out/bench-devices-${points}.las
mkdir -p out
[ -f "$file" ] || build/lasgen --scene deck --points "$points" --order scan -o "$file"
source tools/bench_common.sh
cat "$file" > /dev/null
printf 'points %d (%s MB); cat %.3f s\n' "$points" "$(( $(stat -c %s "$file") / 1000000 ))" "$(best cat "$file")"
build/lasmesh devices
hashes=()
for index in $(build/lasmesh devices | awk '{print $1}'); do
  build/lasmesh grid --grid 1024 --device "$index" "$file" | sed -n 1p
  build/lasmesh grid --grid 1024 --device "$index" "$file" > /dev/null # the kernel cache, warm
  printf '  read + accumulate, grid 1024: %.3f s (best of 3)\n' \
    "$(best build/lasmesh grid --grid 1024 --device "$index" "$file")"
  for _ in 1 2; do
    /usr/bin/time -f '  whole run: %e s, %U s user, %M KB peak' build/lasmesh "$file" --device "$index" \
      -o "out/bench-devices-$index.ply" -o "out/bench-devices-$index.drc" -q
  done
  hash=$(cat "out/bench-devices-$index.ply" "out/bench-devices-$index.drc" | sha256sum | cut -c1-16)
  echo "  outputs' SHA-256: $hash"
  hashes+=("$hash")
done
if [ "$(printf '%s\n' "${hashes[@]}" | sort -u | wc -l)" = 1 ]; then
  echo "every device wrote the same bytes"
else
  echo "devices wrote different bytes" >&2
  exit 1
fi
