#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs what lasmesh needs from Debian 12 (only what is missing), then configures and builds
# it in build/. Idempotent: a second run with nothing changed takes seconds.
# Used by tools/demo.sh and tools/test.sh; run it alone to just build.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  # toolchain
  cmake g++ make pkg-config ccache
  # libraries: LAS streams, parallelism, command line, tests, JSON (command line only), OpenCL, Draco
  libboost-iostreams-dev libtbb-dev libcli11-dev doctest-dev nlohmann-json3-dev
  ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers pocl-opencl-icd clinfo
  libdraco-dev draco libpng-dev libproj-dev libmeshoptimizer-dev zlib1g-dev
  # `lasmesh view`'s web server
  libcpp-httplib-dev
)
# What only the tests and benchmarks use.
test_packages=(
  # compressors for piped input, python3 to read JSON, bc
  gzip bzip2 xz-utils zstd python3 bc
  # the install test renders the man page; the package test builds the .deb (dpkg-shlibdeps)
  groff-base dpkg-dev
  # the viewers test opens the outputs in other programs: assimp (as Open3D and many viewers do)
  assimp-utils python3-open3d
  # the fuzzer (tools/fuzz.sh): clang with libFuzzer and the sanitizer runtimes; the format check
  clang-14 libclang-rt-14-dev clang-format-14
  # the browser test opens tilesets in CesiumJS and three.js in headless Chromium
  chromium
  # the array-job test runs the tiles on a real single-node Slurm (tools/slurm_local.sh)
  slurmctld slurmd slurm-client munge
)
# --demo: what the demo needs and only the targets named (lasmesh, lasgen), so a first run shows a
# mesh after building two programs, not the test suite.
demo=0 targets=()
for arg in "$@"; do
  case $arg in --demo) demo=1 ;; *) targets+=("$arg") ;; esac
done
if [ "$demo" -eq 0 ]; then packages+=("${test_packages[@]}"); fi
# npm (with Node.js) installs three.js and esbuild for the .html viewer (below), and the tests'
# validators and browser packages (tools/test.sh). Checked as a command: a Node.js from elsewhere
# (NodeSource) brings its own npm, and Debian's would clash.
command -v npm > /dev/null || packages+=(npm)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "lasmesh: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# three.js and esbuild, pinned, for the .html output's viewer, bundled into lasmesh when it is
# built (tools/bundle_viewer.sh); once.
viewer_packages=(three@0.187.0 esbuild@0.28.2)
if [ "$(cat build/viewer/installed 2>/dev/null)" != "${viewer_packages[*]}" ]; then
  npm install --prefix build/viewer --no-audit --no-fund --loglevel=error "${viewer_packages[@]}" > /dev/null
  echo "${viewer_packages[*]}" > build/viewer/installed
fi

build_type=${LASMESH_BUILD_TYPE:-Release}
# ccache keeps each compiled object by the hash of its preprocessed source and flags, so building
# the same sources again, in this tree or in another clone of it (paths under the tree are hashed
# relative to it: CCACHE_BASEDIR, CCACHE_NOHASHDIR), takes seconds instead of minutes: a fresh
# clone's test run took 25 minutes on 2 cores with nothing in the cache and 12.5 with the objects
# in it (docs/testing.md, "How long it takes"). tools/test.sh builds build-asan/ through it too.
source tools/ccache_env.sh
# A unity build (CMake compiles the sources in batches, each header parsed once a batch): a fresh
# build took 1m23s instead of 2m36s on 2 cores, with the same output bytes.
# A configure that failed half-way leaves a cache but no Makefile: configure again then; a build
# folder configured without the compiler cache is configured again with it.
if [ ! -f build/Makefile ] || ! grep -qs "^CMAKE_CXX_COMPILER_LAUNCHER:.*=${compiler_launcher}\$" build/CMakeCache.txt; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE="$build_type" -DCMAKE_UNITY_BUILD=ON \
    -DCMAKE_CXX_COMPILER_LAUNCHER="$compiler_launcher" >/dev/null
fi
cmake --build build --parallel "$(nproc)" ${targets[@]:+--target "${targets[@]}"} -- --no-print-directory
