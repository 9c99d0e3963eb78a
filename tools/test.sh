#!/usr/bin/env bash
# The whole test suite on a fresh Debian 12 machine: install, build, run every test (CTest).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh
# The Khronos glTF validator for the .glb tests, pinned, into the build folder; once.
validator_version=2.0.0-dev.3.10
if ! grep -qs "\"version\": \"$validator_version\"" build/gltf-validator/node_modules/gltf-validator/package.json; then
  npm install --prefix build/gltf-validator --no-audit --no-fund --loglevel=error "gltf-validator@$validator_version" > /dev/null
fi
(cd build && ctest --output-on-failure --timeout 900)

# The same tests under AddressSanitizer and UndefinedBehaviorSanitizer, in build-asan/ (GCC, -O1
# to keep them fast). Leak checking is off: PoCL and LLVM keep allocations alive at exit by
# design (docs/design.md); UBSan stops at the first finding.
if [ ! -f build-asan/CMakeCache.txt ]; then
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug \
    -DCMAKE_CXX_FLAGS="-O1 -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined" >/dev/null
fi
cmake --build build-asan --parallel "$(nproc)" -- --no-print-directory
ln -sfn ../build/gltf-validator build-asan/gltf-validator
(cd build-asan && ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure --timeout 900)

# The LAS reader under libFuzzer for a bounded time; `bash tools/fuzz.sh 3600` fuzzes longer.
bash tools/fuzz.sh 60
