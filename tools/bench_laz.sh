#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# LAZ decoding throughput on 1 and 2 threads (build/laz_bench: best of 3, each pass decodes the
# file REPEAT times through LasReader). Files from the shared LAZ corpus:
#   format 1: lone-star (518,862 points, 11 chunks of 50,000), pointwise compressor 2
#   format 3: autzen_trim (110,000 points, 3 chunks), pointwise compressor 2
#   format 7: simple.copc (1,065 points in 65 variable chunks of 6-24), layered compressor 3
#   format 8: las_with_several_extra_byte_bloc (697,721 points, 14 chunks), layered compressor 3
# Each file is then decoded by laz-perf 0.0.7 (tools/laz_perf_bench.js: the reference decoder,
# as WebAssembly under Node.js, installed from npm into build/laz-perf) for a point of comparison.
# Usage: tools/bench_laz.sh [LAZ_FOLDER]   (default ../shared/data/laz)
set -euo pipefail
cd "$(dirname "$0")/.."
laz=${1:-../shared/data/laz}
[ -x build/laz_bench ] || cmake --build build --target laz_bench > /dev/null
[ -d build/laz-perf/node_modules/laz-perf ] ||
  npm install --prefix build/laz-perf --no-audit --no-fund --loglevel=error laz-perf@0.0.7 > /dev/null
# FILE REPEAT REPEAT_LAZ_PERF: laz-perf opens a COPC file in about 0.1 s (its 65 chunks), so it
# decodes that one 5 times, not 500.
for spec in "PDAL_PDAL__test_data_ept_source_lone-star.laz 4 4" "PDAL_PDAL__test_data_laz_autzen_trim.laz 20 20" \
            "laspy_laspy__tests_data_simple.copc.laz 500 5" "PDAL_PDAL__test_data_laz_las_with_several_extra_byte_bloc.laz 3 3"; do
  set -- $spec
  cat "$laz/$1" > /dev/null # page cache
  for threads in 1 2; do build/laz_bench "$laz/$1" "$threads" "$2"; done
  node tools/laz_perf_bench.js "$laz/$1" "$3"
done
