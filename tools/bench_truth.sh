#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The mesh against the deck's true surfaces, part by part (railings, walls, pipes, ...): lasgen
# writes the deck, lasmesh meshes it (default options, or the ones given), and `lasgen --measure`
# measures the PLY against the analytic primitives the points were drawn from.
# Usage: bash tools/bench_truth.sh [POINTS] [lasmesh options...]   (default 20,000,000 points)
# Prints the cost (time, peak memory, triangles, Draco bytes) and the table by part.
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-20000000}
shift || true
mkdir -p out/bench
las=out/bench/deck-$points.las
[ -s "$las" ] || build/lasgen --scene deck --points "$points" -o "$las"
tag=$(printf '%s' "$*" | tr -c 'A-Za-z0-9.=-' '_')
base=out/bench/truth-$points${tag:+-$tag}
build/lasmesh "$las" "$@" -o "$base.ply" -o "$base.drc" --report "$base.json" -q
python3 - "$base.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
drc = [o["bytes"] for o in r["outputs"] if o["path"].endswith(".drc")][0]
g = r["grid"]
print(f"{r['points_read']:,} points, grid {'x'.join(map(str, g['dims']))} of {100 * g['cell_size']:.1f} cm: "
      f"{r['seconds']['total']:.1f} s, peak {r['peak_rss_bytes'] / 1e6:.0f} MB, {r['triangles']:,} triangles, "
      f"Draco {drc / 1e3:.0f} kB\n")
PY
build/lasgen --scene deck --measure "$base.ply" --json "$base.truth.json"
