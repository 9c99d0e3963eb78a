// SPDX-License-Identifier: Apache-2.0
// Internal: the OpenCL sources of kernels/*.cl, embedded at build time (see CMakeLists.txt) so
// an installed lasmesh runs from any directory.
#pragma once

namespace lasmesh::kernels {
extern const char accumulate[];
}
