#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The .html page's frame rate while orbiting (tools/page_fps.js) on a generated deck's default
# mesh, in headless Chromium: software rendering (SwiftShader) by default, the GPU with --gpu.
# Usage: tools/bench_page_fps.sh [POINTS] [--gpu]   (default 2,000,000 points)
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-2000000}
shift || true
work=$(mktemp -d) && trap 'rm -rf "$work"' EXIT
build/lasgen --scene deck -n "$n" --seed 1 -o "$work/deck.las" > /dev/null
build/lasmesh "$work/deck.las" -o "$work/deck.html" -q
printf 'points %d, page %d bytes, %d cores\n' "$n" "$(stat -c %s "$work/deck.html")" "$(nproc)"
node tools/page_fps.js build/browser "$work/deck.html" "$@"
