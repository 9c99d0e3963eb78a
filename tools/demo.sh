#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The main job on a built-in default: install, build, generate a sample deck scan (2 million
# points, the kind of scene lasmesh is for), report on it, mesh it to PLY, Draco, glTF and a page
# for the browser with a preview picture in one run, and measure how close the mesh is to the points.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh --demo lasmesh lasgen
mkdir -p out
sample=out/sample-deck.las
[ -f "$sample" ] || build/lasgen --scene deck --points 2000000 --seed 1 -o "$sample"
build/lasmesh info --scan "$sample"
echo
build/lasmesh "$sample" -o out/sample-deck.ply -o out/sample-deck.drc -o out/sample-deck.glb -o out/sample-deck.html \
  --preview out/sample-deck.png
echo
build/lasmesh compare out/sample-deck.ply "$sample" --samples 500000 --heatmap out/sample-deck-distance.ply
echo
echo "meshes in out/: sample-deck.ply (MeshLab, CloudCompare, Blender), sample-deck.glb (three.js, Blender),"
echo "sample-deck.drc (Draco), sample-deck-distance.ply (the mesh coloured by its distance to the points),"
echo "sample-deck.png (a picture of the mesh: four views), sample-deck.html (open it in a web browser: look, measure, cut)"
