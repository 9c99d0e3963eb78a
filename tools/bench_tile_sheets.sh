#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The sheet meshed tile by tile against the whole grid's, on the generated deck: the tiles'
# sheets (each from its cells and a halo, with the survey, the planes' facing and the parts'
# turns decided from what the tiles hand on) joined, and the whole grid's; the triangles only one
# of them has, and both against the deck's true surfaces (lasgen --measure).
# Usage: tools/bench_tile_sheets.sh [POINTS] [TILE] [HALO] [--thin]   (default 2,000,000 points, 64, 8)
# --thin: both meshes with the thin parts meshed at half the cell and joined to the sheet (the
# whole grid's as one tile), and whether the tiles find the whole grid's thin cells and sample the
# seam as its sheet does.
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-2000000} tile=${2:-64} halo=${3:-8}
mkdir -p out/bench
las=out/bench/deck-$points.las
[ -s "$las" ] || build/lasgen --scene deck --points "$points" -o "$las"
suffix=""
for option in "${@:4}"; do suffix+="${option#-}"; done
prefix=out/bench/tile-sheets-$points-$tile-$halo$suffix
build/tile_sheets_bench "$las" "$tile" "$halo" "$prefix" "${@:4}"
for mesh in whole tiled; do
  echo; echo "$mesh:"
  build/lasgen --scene deck --measure "$prefix-$mesh.ply"
done
