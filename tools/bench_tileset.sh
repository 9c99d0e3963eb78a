#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# A 3D Tiles tileset against the single mesh at the same finest grid, same run: the whole run's
# time and peak memory (best of 2 each, from --report), the root tile's bytes, and per level the
# cell, tiles, triangles and measured geometric error; fails unless the finest level holds the
# triangles of a mesh written beside the tileset (it is that mesh, cut into tiles). The single
# mesh written alone has the same sheet in another order (a tileset's comes tile by tile), so
# its simplification differs a little: both counts are printed.
# Usage: tools/bench_tileset.sh [POINTS] [GRID]   (defaults 5,000,000 and auto)
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-5000000} grid=${2:-auto}
work=$(mktemp -d) && trap 'rm -rf "$work"' EXIT
build/lasgen --scene deck -n "$n" --order scan --epsg 32631 -o "$work/deck.las" > /dev/null
mkdir -p "$work/site"
field() { python3 -c "import json, sys; r = json.load(open(sys.argv[1])); print(r['seconds']['total'], r['peak_rss_bytes'])" "$1"; }
triangles() { python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['triangles'])" "$1"; }
best() { # best of 2: total seconds and peak bytes
  local name=$1 t=999 m=0
  shift
  for _ in 1 2; do
    build/lasmesh "$@" --grid "$grid" -q --report "$work/$name.json"
    read -r total peak < <(field "$work/$name.json")
    t=$(echo "if ($total < $t) $total else $t" | bc -l) m=$peak
  done
  echo "$t $m"
}
read -r t_single m_single < <(best single "$work/deck.las" -o "$work/single.glb")
read -r t_tiles m_tiles < <(best tiles "$work/deck.las" -o "$work/site/tileset.json")
mkdir -p "$work/beside" # untimed: the tileset with a mesh beside it, in the tiles' order
build/lasmesh "$work/deck.las" --grid "$grid" -q -o "$work/beside/tileset.json" -o "$work/beside.glb" \
  --report "$work/beside.json"
printf 'points %d, grid %s, %d cores\n' "$n" "$grid" "$(nproc)"
printf 'single .glb:  %.3f s, %d MB peak\n' "$t_single" "$((m_single / 1000000))"
printf 'tileset:      %.3f s, %d MB peak  (%.2fx the time, %.2fx the memory)\n' "$t_tiles" "$((m_tiles / 1000000))" \
  "$(echo "$t_tiles / $t_single" | bc -l)" "$(echo "$m_tiles / $m_single" | bc -l)"
python3 - "$work/site/tileset.json" "$(triangles "$work/beside.json")" "$(triangles "$work/single.json")" <<'PY'
import json, os, sys
path, single, alone = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
t = json.load(open(path))
root = t["root"]["content"]["uri"]
print(f"root tile: {os.path.getsize(os.path.join(os.path.dirname(path), root))} bytes")
print("level  cell (m)  tiles  triangles  geometric error (m)")
for k, level in enumerate(t["extras"]["lasmesh"]["levels"]):
    print(f"{k:5d}  {level['cell_size']:8.4f}  {level['tiles']:5d}  {level['triangles']:9d}  {level['geometric_error']:.4f}")
finest = t["extras"]["lasmesh"]["levels"][-1]["triangles"]
print(f"finest level {finest} triangles, the mesh beside it {single}: {'the same mesh' if finest == single else 'DIFFERENT'}; "
      f"the single mesh alone {alone}")
sys.exit(0 if finest == single else 1)
PY
