#!/usr/bin/env bash
# The whole test suite on a fresh Debian 12 machine: install, build, run every test (CTest).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh
cd build
ctest --output-on-failure --timeout 900
