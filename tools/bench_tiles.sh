#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The deck as a survey of SPLIT x SPLIT map-tile files (lasgen --split-xy), meshed to a 3D Tiles tileset on
# this machine in one run, then planned, run as a Slurm array job on a single-node cluster
# (tools/slurm_local.sh, as root) and merged:
#   - whether the merged tileset is the one run's, every file byte for byte;
#   - CPU seconds (user + system) of the one run against all tile jobs and the merge together;
#   - each tile job's wall time and peak resident memory, against the one run's peak / tiles;
#   - the bytes each tile job read (its inputs' sizes) against the whole survey's.
# Usage: tools/bench_tiles.sh [POINTS] [TILE] [SPLIT] [TILE OPTIONS...]
#   (default 20,000,000 points, tiles of 10 m, 4 x 4 files; e.g. --chunk-mb 4 for every tile job)
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-20000000} tile=${2:-10} split=${3:-4}
tile_options=("${@:4}")
root=$(pwd) lasmesh=$(pwd)/build/lasmesh lasgen=$(pwd)/build/lasgen
work=$(mktemp -d /tmp/lasmesh-tiles-XXXXXX) && chmod 0755 "$work"
mkdir "$work/cluster"
trap '"$root/tools/slurm_local.sh" stop "$work/cluster" || true; rm -rf "$work"' EXIT
cd "$work"
"$lasgen" --scene deck -n "$n" --seed 1 --epsg 32631 --split-xy "$split" -o deck.las
mkdir one many
/usr/bin/time -f "%e %U %S %M" -o one.time "$lasmesh" deck-*.las --tile "$tile" -o one/tileset.json -q
read -r one_wall one_user one_sys one_kb < one.time
"$lasmesh" plan deck-*.las --tile "$tile" -o site.plan.json > plan.txt
head -1 plan.txt
tiles=$(python3 -c 'import json; print(len(json.load(open("site.plan.json"))["tiles"]))')
# Each task under /usr/bin/time: its wall, CPU and peak memory, one line a task.
printf '#!/bin/bash\nexec /usr/bin/time -a -o %s -f "%%e %%U %%S %%M" %s "$@"\n' "$work/tiles.time" "$lasmesh" > timed
chmod +x timed
eval "$("$root/tools/slurm_local.sh" start cluster)"
start=$(date +%s.%N)
sbatch --wait --array=0-$((tiles - 1)) --export=ALL,LASMESH="$work/timed" "$root/deploy/slurm/lasmesh-tile.sbatch" \
  site.plan.json "${tile_options[@]}" > /dev/null
array_wall=$(echo "$(date +%s.%N) - $start" | bc)
/usr/bin/time -f "%e %U %S %M" -o merge.time "$lasmesh" merge site.plan.json -o many/tileset.json -q
read -r merge_wall merge_user merge_sys merge_kb < merge.time
identical=no
diff -r one many > /dev/null && identical=yes
python3 - "$one_user" "$one_sys" "$one_kb" "$one_wall" "$merge_user" "$merge_sys" "$merge_kb" "$merge_wall" \
  "$array_wall" "$identical" <<'PY'
import json, os, sys
one_user, one_sys, one_kb, one_wall, m_user, m_sys, m_kb, m_wall, array_wall = map(float, sys.argv[1:10])
identical = sys.argv[10]
rows = [list(map(float, l.split())) for l in open("tiles.time") if l.strip() and l[0].isdigit()]
plan = json.load(open("site.plan.json"))
sizes = [i["bytes"] for i in plan["inputs"]]
read = [sum(sizes[i] for i in t["inputs"]) for t in plan["tiles"]]
one_cpu = one_user + one_sys
tiles_cpu = sum(r[1] + r[2] for r in rows)
share = one_kb / 1024 / len(rows)
print(f"tiles {len(rows)}; identical tileset: {identical}")
print(f"one run      wall {one_wall:.1f} s, CPU {one_cpu:.1f} s, peak {one_kb / 1024:.0f} MB")
print(f"tile jobs    CPU {tiles_cpu:.1f} s in all; wall per job {min(r[0] for r in rows):.1f}-{max(r[0] for r in rows):.1f} s; "
      f"peak per job {min(r[3] for r in rows) / 1024:.0f}-{max(r[3] for r in rows) / 1024:.0f} MB "
      f"(one run's peak / tiles = {share:.0f} MB); the array {array_wall:.1f} s on this machine")
print(f"merge        wall {m_wall:.1f} s, CPU {m_user + m_sys:.1f} s, peak {m_kb / 1024:.0f} MB")
print(f"CPU, tiles + merge / one run: {(tiles_cpu + m_user + m_sys) / one_cpu:.2f}")
print(f"bytes read per tile job: {min(read) / 1e6:.0f}-{max(read) / 1e6:.0f} MB of {sum(sizes) / 1e6:.0f} MB; "
      f"all jobs together {sum(read) / sum(sizes):.2f} x the survey")
PY
