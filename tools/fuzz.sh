#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Fuzzes the LAS and LAZ reader (tools/fuzz/fuzz_las.cpp) with libFuzzer under AddressSanitizer and
# UndefinedBehaviorSanitizer for SECONDS (default 60); exits non-zero on any crash, leaving the
# input that caused it in build-fuzz/artifacts/. Needs build/lasgen (tools/build.sh) for the seeds.
# Longer runs: `bash tools/fuzz.sh 3600`; the corpus in build-fuzz/corpus/ grows across runs.
# Usage: tools/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
out=build-fuzz
mkdir -p "$out/seeds" "$out/corpus" "$out/artifacts"

# Compiled directly (no CMake): the target needs only the reading sources and Boost.Iostreams.
sources=(tools/fuzz/fuzz_las.cpp src/error.cpp src/read/input_stream.cpp src/read/las_header.cpp src/read/las_reader.cpp
         src/read/las_scan.cpp src/read/arithmetic_decoder.cpp src/read/laz_vlr.cpp src/read/laz_items_v2.cpp
         src/read/laz_pointwise.cpp src/read/laz_layered.cpp src/read/laz_chunks.cpp src/read/laz_decoder.cpp
         src/read/crs.cpp)
if [ ! -x "$out/fuzz_las" ] || [ -n "$(find "${sources[@]}" include -newer "$out/fuzz_las" | head -1)" ]; then
  # One object per source, compiled in parallel, then linked.
  flags=(-std=c++20 -O1 -g -fno-omit-frame-pointer -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined
         -Iinclude -Isrc)
  mkdir -p "$out/objects"
  objects=()
  for source in "${sources[@]}"; do objects+=("$out/objects/$(echo "$source" | tr / _).o"); done
  running=()
  source tools/ccache_env.sh # the objects through the compiler cache, as the other builds
  for i in "${!sources[@]}"; do
    $compiler_launcher clang++-14 "${flags[@]}" -c "${sources[$i]}" -o "${objects[$i]}" &
    running+=($!)
    if [ ${#running[@]} -ge "$(nproc)" ]; then wait "${running[0]}"; running=("${running[@]:1}"); fi # set -e: a failure stops here
  done
  for pid in "${running[@]}"; do wait "$pid"; done
  clang++-14 "${flags[@]}" "${objects[@]}" -lboost_iostreams -ltbb -lproj -o "$out/fuzz_las"
fi

# Seeds: small valid files of every version and point format, some with extra bytes, and the
# same compressed with each supported compressor (so the decoders are reached too).
lasgen=build/lasgen
for version in 1.0 1.1 1.2 1.3 1.4; do
  formats="0 1"
  [ "$version" = 1.2 ] && formats="0 1 2 3"
  [ "$version" = 1.3 ] && formats="0 1 2 3 4 5"
  [ "$version" = 1.4 ] && formats="0 1 2 3 4 5 6 7 8 9 10"
  for format in $formats; do
    "$lasgen" --scene sphere --points 12 --las-version "$version" --format "$format" \
      -o "$out/seeds/v$version-f$format.las"
  done
done
"$lasgen" --scene box --points 20 --format 2 --extra-bytes 5 -o "$out/seeds/extra.las"
"$lasgen" --scene box --points 20 --epsg 32631 -o "$out/seeds/crs.las" # GeoTIFF keys for read_crs
gzip -c "$out/seeds/v1.2-f3.las" > "$out/seeds/v1.2-f3.las.gz"
bzip2 -c "$out/seeds/v1.4-f7.las" > "$out/seeds/v1.4-f7.las.bz2"
xz -c "$out/seeds/v1.3-f1.las" > "$out/seeds/v1.3-f1.las.xz"
zstd -q -c "$out/seeds/v1.0-f0.las" > "$out/seeds/v1.0-f0.las.zst"
# LAZ (issue 18): the small files of the shared corpus, when it is there: pointwise and layered,
# fixed and variable chunks, from a file (chunk table) and gzip-compressed (sequential decoding).
laz=${LASMESH_SHARED:-../shared}/data/laz
if [ -d "$laz" ]; then
  for f in laspy_laspy__tests_data_simple.laz laspy_laspy__tests_data_1_4_w_evlr.laz \
           PDAL_PDAL__test_data_tindex_autzen_clip_native.copc.laz laspy_laspy__tests_data_extra.laz; do
    [ -f "$laz/$f" ] && cp "$laz/$f" "$out/seeds/" && gzip -c "$laz/$f" > "$out/seeds/$f.gz"
  done
fi

# -timeout: one input taking 30 s is a hang (sanitized, on a loaded 2-core machine, a slow but
# finite input takes seconds); -rss_limit_mb: no input may need much memory.
"$out/fuzz_las" "$out/corpus" "$out/seeds" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2048 \
  -artifact_prefix="$out/artifacts/" -print_final_stats=1 -close_fd_mask=3 2>&1 |
  grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb|Done|==|SUMMARY|INFO: seed corpus)|ERROR|runtime error" || true
exit "${PIPESTATUS[0]}"
