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
cd build
ctest --output-on-failure --timeout 900
