#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The tiles as a real Slurm array job: a single-node cluster (tools/slurm_local.sh: Debian's
# munged, slurmctld, slurmd) runs deploy/slurm/lasmesh-tile.sbatch with sbatch --array; merge
# then writes the tileset and PLY that one run writes, byte for byte. A failed task is rerun alone.
# Skipped (77) without root or Slurm's packages.
# Usage: slurm_test.sh LASMESH LASGEN
set -u
lasmesh=$1 lasgen=$2 here=$(dirname "$0")
root=$(cd "$here/../.." && pwd)
source "$here/common.sh"
cd "$dir" || exit 1

mkdir cluster
chmod 0755 "$dir" # munge's socket must be reachable by all
"$root/tools/slurm_local.sh" start cluster > cluster.env 2> cluster.err; rc=$?
if [ "$rc" -eq 77 ]; then
  cat cluster.err
  echo "slurm_array: skipped (no Slurm here)"
  exit 77
fi
trap '"$root/tools/slurm_local.sh" stop "$dir/cluster"; chmod -R u+w "$dir"; rm -rf "$dir"' EXIT
check "a single-node Slurm starts" test "$rc" -eq 0
[ "$rc" -eq 0 ] || { cat cluster.err; finish slurm_array; exit; }
source cluster.env

"$lasgen" --scene deck --points 300000 --seed 6 --epsg 32631 --split-xy 3 -o deck.las > /dev/null
mkdir one many again in-tiles
"$lasmesh" deck-*.las --tile 16 -o one/tileset.json -o one/mesh.ply -q
"$lasmesh" plan deck-*.las --tile 16 -o site.plan.json > plan.txt
tiles=$(python3 -c 'import json; print(len(json.load(open("site.plan.json"))["tiles"]))')
timeout 300 sbatch --wait --array=0-$((tiles - 1)) --export=ALL,LASMESH="$lasmesh" \
  "$root/deploy/slurm/lasmesh-tile.sbatch" site.plan.json > sbatch.txt 2>&1; rc=$?
check "sbatch --array --wait: every task succeeded" test "$rc" -eq 0
check "sbatch ran them as one array job" contains sbatch.txt "Submitted batch job [0-9]"
check "each task wrote its tile" test "$(ls site.plan-tiles | wc -l)" -eq "$tiles"
check "each task logged its tile" test "$(cat lasmesh-tile-*_*.out | grep -c '^tile [0-9]* of ')" -eq "$tiles"
"$lasmesh" merge site.plan.json -o many/tileset.json -o many/mesh.ply -q; rc=$?
check "merge: exit 0" test "$rc" -eq 0
check "Slurm's tileset = one run's, every file byte for byte" diff -r one many
"$lasmesh" merge site.plan.json --in-tiles -o in-tiles/tileset.json -o in-tiles/mesh.ply -q
check "and merged --in-tiles (the sheet meshed tile by tile)" diff -r one in-tiles

# One task rerun alone replaces its tile; the result is unchanged.
rm site.plan-tiles/tile-1.cells
"$lasmesh" merge site.plan.json -o many/mesh.ply -q 2> missing.txt
check "a tile missing: merge names it" has missing.txt "sbatch --array=1 "
timeout 120 sbatch --wait --array=1 --export=ALL,LASMESH="$lasmesh" "$root/deploy/slurm/lasmesh-tile.sbatch" \
  site.plan.json > /dev/null 2>&1; rc=$?
check "the one task rerun succeeds" test "$rc" -eq 0
"$lasmesh" merge site.plan.json -o again/tileset.json -o again/mesh.ply -q
check "and the merge is the same" cmp -s one/mesh.ply again/mesh.ply
finish slurm_array
