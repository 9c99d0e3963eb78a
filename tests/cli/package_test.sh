#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The Debian package: `cpack -G DEB` builds it; its metadata names the libraries it links and an
# OpenCL driver; it holds the command, the man page, the licence, the headers and the CMake
# package; and the command unpacked from it runs and meshes.
# Usage: package_test.sh BUILD_DIR LASGEN
set -u
build=$1 lasgen=$2
source "$(dirname "$0")/common.sh"

(cd "$build" && cpack -G DEB -B "$dir/out" > "$dir/cpack.log" 2>&1)
check "cpack builds the .deb" test $? -eq 0 || tail -20 "$dir/cpack.log"
deb=$(ls "$dir"/out/lasmesh_*.deb 2>/dev/null | head -1)
check "one package, named by version and architecture" test -n "$deb"
[ -n "$deb" ] || { finish "package"; exit; }
dpkg-deb -f "$deb" Depends > "$dir/depends.txt"
for library in libtbb libboost-iostreams libdraco libpng16-16 ocl-icd-libopencl1 libcpp-httplib libstdc++6; do
  check "depends on $library (from the linked libraries)" contains "$dir/depends.txt" "$library"
done
check "depends on an OpenCL driver" has "$dir/depends.txt" "pocl-opencl-icd | opencl-icd"
dpkg-deb -c "$deb" > "$dir/contents.txt"
for path in ./usr/bin/lasmesh ./usr/share/man/man1/lasmesh.1 ./usr/share/doc/lasmesh/LICENSE \
            ./usr/include/lasmesh/build_mesh.hpp ./usr/lib/cmake/lasmesh/lasmeshConfig.cmake; do
  check "the package holds $path" contains "$dir/contents.txt" " $path\$"
done
# What `apt install ./lasmesh_*.deb` would do here, simulated (no root needed, nothing changed):
# every dependency resolves against Debian's packages.
apt-get install -s --no-install-recommends "$deb" > "$dir/apt.txt" 2>&1
check "apt resolves the package's dependencies (simulated install)" grep -q "^Inst lasmesh " "$dir/apt.txt" ||
  tail -5 "$dir/apt.txt"
dpkg-deb -x "$deb" "$dir/root"
"$dir/root/usr/bin/lasmesh" --version > "$dir/version.txt"
check "the packaged command runs" contains "$dir/version.txt" "^lasmesh $(dpkg-deb -f "$deb" Version)"
"$lasgen" --scene sphere --points 20000 -o "$dir/s.las"
"$dir/root/usr/bin/lasmesh" "$dir/s.las" -o "$dir/s.glb" -q
check "the packaged command meshes" test -s "$dir/s.glb"

finish "package"
