#!/usr/bin/env bash
# The main job on a built-in default: install, build, generate a sample deck scan (2 million
# points, the kind of scene lasmesh is for), report on it, and mesh it to out/sample-deck.ply.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh
mkdir -p out
sample=out/sample-deck.las
[ -f "$sample" ] || build/lasgen --scene deck --points 2000000 --seed 1 -o "$sample"
build/lasmesh info --scan "$sample"
echo
build/lasmesh "$sample" -o out/sample-deck.ply
echo "mesh written to out/sample-deck.ply (open it in MeshLab, CloudCompare or Blender)"
