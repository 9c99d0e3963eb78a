# SPDX-License-Identifier: Apache-2.0
# lasmesh in a container: built from this checkout on Debian 12, packaged as a .deb, installed
# into Debian 12 slim with PoCL (the CPU as OpenCL device).
#   docker build -t lasmesh .
#   docker run --rm -v "$PWD:/data" lasmesh /data/deck.las -o /data/deck.glb
FROM debian:12 AS build
RUN apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      cmake g++ make pkg-config dpkg-dev file \
      libboost-iostreams-dev libtbb-dev libcli11-dev doctest-dev nlohmann-json3-dev \
      ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers libdraco-dev > /dev/null
COPY . /src
RUN cmake -S /src -B /build -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON -DLASMESH_BUILD_TESTS=OFF > /dev/null \
 && cmake --build /build --parallel "$(nproc)" --target lasmesh man_page \
 && cd /build && cpack -G DEB -B /deb

FROM debian:12-slim
COPY --from=build /deb/lasmesh_*.deb /tmp/
RUN apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      /tmp/lasmesh_*.deb pocl-opencl-icd > /dev/null \
 && rm -rf /var/lib/apt/lists/* /tmp/lasmesh_*.deb
ENTRYPOINT ["lasmesh"]
