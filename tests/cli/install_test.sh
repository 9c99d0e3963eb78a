#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# `cmake --install` gives the command, the man page, the headers and a CMake package that a
# separate project finds with find_package(lasmesh) and links.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR LASGEN
set -u
build=$1 source=$2 lasgen=$3
source "$(dirname "$0")/common.sh"

cmake --install "$build" --prefix "$dir/prefix" > "$dir/install.log"
check "the command is installed and runs" "$dir/prefix/bin/lasmesh" --version
check "the man page is installed" test -s "$dir/prefix/share/man/man1/lasmesh.1"
check "the man page renders" bash -c "groff -man -Tutf8 -P-cbou -ww '$dir/prefix/share/man/man1/lasmesh.1' 2>&1 | grep -q '^EXIT STATUS'"
# Written from the same declarations as --help: every option of every command is in it.
man=$dir/prefix/share/man/man1/lasmesh.1
missing=""
for command in "" info grid compare; do
  for option in $("$dir/prefix/bin/lasmesh" $command --help | grep -o -- '--[a-z][a-z-]*' | sort -u); do
    grep -qF -- "${option//-/\\-}" "$man" || missing+=" $command$option"
  done
done
check "the man page has every option --help shows" test -z "$missing" || echo "missing from the man page:$missing"
"$dir/prefix/bin/lasmesh" --help > "$dir/help.txt"
check "--help shows value lists as users type them" has "$dir/help.txt" "--surface sheet|closed"
check "... and no CLI11 type notes" lacks "$dir/help.txt" "POSITIVE"
check "... nor exclusion notes" lacks "$dir/help.txt" "Excludes"
check "the man page has each command's examples" grep -qF 'lasmesh compare deck.drc deck.las \-\-json' "$man"
installed=$(cd "$dir/prefix/include/lasmesh" && ls)
check "the public headers are installed, and only they" test "$installed" = "$(cd "$source/include/lasmesh" && ls)"
check "the public API is at most 12 headers" test "$(echo "$installed" | wc -l)" -le 12
alone=""
for header in $installed; do
  echo "#include <lasmesh/$header>" | g++ -std=c++20 -fsyntax-only -x c++ -I "$dir/prefix/include" - 2> /dev/null || alone+=" $header"
done
check "each public header compiles on its own (no internal header behind it)" test -z "$alone" || echo "not alone:$alone"
check "the library is installed" test -s "$dir/prefix/lib/liblasmesh.a"
check "the package config is installed" test -s "$dir/prefix/lib/cmake/lasmesh/lasmeshConfig.cmake"
targets=$(ls "$dir"/prefix/lib/cmake/lasmesh/lasmeshTargets.cmake)
check "the exported target carries C++20" grep -q 'INTERFACE_COMPILE_FEATURES "cxx_std_20"' "$targets"
check "the exported link interface names no empty generator expression" lacks "$targets" 'LINK_ONLY:>'
check "the licence is installed" test -s "$dir/prefix/share/doc/lasmesh/LICENSE"

# The consumer is compiled like the library (the sanitizer build's flags, when testing that one).
flags=$(sed -n 's/^CMAKE_CXX_FLAGS:[A-Z]*=//p' "$build/CMakeCache.txt")
cmake -S "$source/tests/consumer" -B "$dir/consumer" -DCMAKE_PREFIX_PATH="$dir/prefix" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_FLAGS="$flags" > "$dir/configure.log" 2>&1
check "find_package(lasmesh) configures" test $? -eq 0 || cat "$dir/configure.log"
cmake --build "$dir/consumer" > "$dir/build.log" 2>&1
check "the consumer builds and links" test $? -eq 0 || tail -20 "$dir/build.log"
"$lasgen" --scene sphere --points 20000 -o "$dir/s.las"
"$dir/consumer/consumer" "$dir/s.las" "$dir/lib.glb" "$dir/s.ply" > "$dir/out.txt"
check "the consumer's build_mesh calls succeed" test $? -eq 0
check "the consumer reads and meshes" grep -q "^20000 points, [1-9][0-9]* triangles" "$dir/out.txt"
check "the consumer's mesh is closed" grep -q "triangles, closed$" "$dir/out.txt"
check "the consumer's PLY is written" test -s "$dir/s.ply"
check "the consumer reads the points back and measures its mesh against them" \
  grep -q "^read 20000 points; half of them within [0-9.e-]* of the mesh$" "$dir/out.txt"
# BuildOptions{} is the command line's default run: the same bytes.
"$dir/prefix/bin/lasmesh" "$dir/s.las" -o "$dir/cli.glb" -q
check "BuildOptions{} writes what the command writes with no options" cmp "$dir/lib.glb" "$dir/cli.glb"
"$lasgen" --scene deck --points 200000 -o "$dir/d.las"
"$dir/consumer/consumer" "$dir/d.las" "$dir/lib-deck.drc" "$dir/d.ply" > /dev/null
"$dir/prefix/bin/lasmesh" "$dir/d.las" -o "$dir/cli-deck.drc" -q
check "... on a deck, in Draco too" cmp "$dir/lib-deck.drc" "$dir/cli-deck.drc"

finish "install"
