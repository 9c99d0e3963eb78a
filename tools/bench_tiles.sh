#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The deck as a survey of SPLIT x SPLIT map-tile files (lasgen --split-xy), meshed to a 3D Tiles tileset on
# this machine in one run, then planned, run as a Slurm array job on a single-node cluster
# (tools/slurm_local.sh, as root) and merged:
#   - whether the merged tileset is the one run's, every file byte for byte;
#   - CPU seconds (user + system) of the one run against all tile jobs and the merge together;
#   - each tile job's wall time and peak resident memory, against the one run's peak / tiles;
#   - the bytes each tile job read (its inputs' sizes) against the whole survey's.
# Usage: [ROUNDS=R] tools/bench_tiles.sh [POINTS] [TILE] [SPLIT] [TILE OPTIONS...]
#   (default 20,000,000 points, tiles of 10 m, 4 x 4 files, 3 rounds; e.g. --chunk-mb 4 for every tile job)
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-20000000} tile=${2:-10} split=${3:-4}
tile_options=("${@:4}") rounds=${ROUNDS:-3}
root=$(pwd) lasmesh=$(pwd)/build/lasmesh lasgen=$(pwd)/build/lasgen
work=$(mktemp -d /tmp/lasmesh-tiles-XXXXXX) && chmod 0755 "$work"
mkdir "$work/cluster"
trap '"$root/tools/slurm_local.sh" stop "$work/cluster" || true; rm -rf "$work"' EXIT
cd "$work"
"$lasgen" --scene deck -n "$n" --seed 1 --epsg 32631 --split-xy "$split" -o deck.las
"$lasmesh" plan deck-*.las --tile "$tile" -o site.plan.json > plan.txt
head -1 plan.txt
tiles=$(python3 -c 'import json; print(len(json.load(open("site.plan.json"))["tiles"]))')
eval "$("$root/tools/slurm_local.sh" start cluster)"
# Each round: the one run, then the array job and the merge, each under /usr/bin/time (a tile job's
# wall, CPU and peak memory, one line a task). The rounds alternate the two ways, so that this
# machine's drift (a shared virtual machine's CPU seconds vary by a third between minutes) falls
# on both; the median round's ratio is the figure.
for round in $(seq 1 "$rounds"); do
  rm -rf one many site.plan-tiles && mkdir one many
  /usr/bin/time -f "%e %U %S %M" -o "one-$round.time" "$lasmesh" deck-*.las --tile "$tile" -o one/tileset.json -q
  printf '#!/bin/bash\nexec /usr/bin/time -a -o %s -f "%%e %%U %%S %%M" %s "$@"\n' "$work/tiles-$round.time" "$lasmesh" > timed
  chmod +x timed
  start=$(date +%s.%N)
  sbatch --wait --array=0-$((tiles - 1)) --export=ALL,LASMESH="$work/timed" "$root/deploy/slurm/lasmesh-tile.sbatch" \
    site.plan.json "${tile_options[@]}" > /dev/null
  echo "$(date +%s.%N) - $start" | bc > "array-$round.wall"
  /usr/bin/time -f "%e %U %S %M" -o "merge-$round.time" "$lasmesh" merge site.plan.json -o many/tileset.json -q
  if diff -r one many > /dev/null; then echo yes; else echo no; fi > "identical-$round"
done
python3 - "$rounds" <<'PY'
import json, statistics, sys
rounds = int(sys.argv[1])
plan = json.load(open("site.plan.json"))
sizes = [i["bytes"] for i in plan["inputs"]]
read = [sum(sizes[i] for i in t["inputs"]) for t in plan["tiles"]]
fields = lambda path: list(map(float, open(path).read().split()))
ratios = []
for r in range(1, rounds + 1):
    one_wall, one_user, one_sys, one_kb = fields(f"one-{r}.time")
    m_wall, m_user, m_sys, m_kb = fields(f"merge-{r}.time")
    rows = [list(map(float, l.split())) for l in open(f"tiles-{r}.time") if l.strip() and l[0].isdigit()]
    one_cpu, tiles_cpu = one_user + one_sys, sum(row[1] + row[2] for row in rows)
    share = one_kb / 1024 / len(rows)
    ratios.append((tiles_cpu + m_user + m_sys) / one_cpu)
    print(f"round {r}: tiles {len(rows)}; identical tileset: {open(f'identical-{r}').read().strip()}")
    print(f"  one run      wall {one_wall:.1f} s, CPU {one_cpu:.1f} s, peak {one_kb / 1024:.0f} MB")
    print(f"  tile jobs    CPU {tiles_cpu:.1f} s in all; wall per job {min(x[0] for x in rows):.1f}-{max(x[0] for x in rows):.1f} s; "
          f"peak per job {min(x[3] for x in rows) / 1024:.0f}-{max(x[3] for x in rows) / 1024:.0f} MB "
          f"(one run's peak / tiles = {share:.0f} MB); the array {float(open(f'array-{r}.wall').read()):.1f} s on this machine")
    print(f"  merge        wall {m_wall:.1f} s, CPU {m_user + m_sys:.1f} s, peak {m_kb / 1024:.0f} MB")
    print(f"  CPU, tiles + merge / one run: {ratios[-1]:.2f}")
print(f"CPU, tiles + merge / one run: median {statistics.median(ratios):.2f} of {rounds} rounds "
      f"({', '.join(f'{x:.2f}' for x in ratios)})")
print(f"bytes read per tile job: {min(read) / 1e6:.0f}-{max(read) / 1e6:.0f} MB of {sum(sizes) / 1e6:.0f} MB; "
      f"all jobs together {sum(read) / sum(sizes):.2f} x the survey")
PY
