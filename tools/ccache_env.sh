# SPDX-License-Identifier: Apache-2.0
# Sourced by tools/build.sh, tools/test.sh and tools/fuzz.sh from the tree's root: compile through
# ccache when it is installed (tools/build.sh installs it), with paths under the tree hashed
# relative to it, so another clone of the same sources (a CI run's) finds the objects this one
# compiled. Sets compiler_launcher to the launcher for CMAKE_CXX_COMPILER_LAUNCHER ("" without).
compiler_launcher=""
if command -v ccache > /dev/null; then
  compiler_launcher=ccache
  # Debug information then names the first tree that compiled an object (CCACHE_NOHASHDIR):
  # sanitizer reports still name the files and lines.
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
fi
