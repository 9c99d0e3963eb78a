// SPDX-License-Identifier: Apache-2.0
// The OpenCL devices that can sum the points into the grid (BuildOptions::device picks one).
//
//     for (const lasmesh::DeviceInfo& d : lasmesh::list_devices())   // throws lasmesh::Error (device)
//         std::cout << d.index << " " << d.name << " (" << d.type << ")\n";
//
// PoCL on the CPU works everywhere; a GPU is preferred when one is present.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lasmesh {

struct DeviceInfo {
    int index = 0; // position in list_devices(), across all platforms
    std::string platform;
    std::string name;
    std::string type;    // "GPU", "CPU", "accelerator" or "other"
    std::string version; // the device's OpenCL version string
    std::uint64_t global_memory = 0;
    std::uint64_t max_alloc = 0; // CL_DEVICE_MAX_MEM_ALLOC_SIZE: the largest single buffer
};

// Every device of every OpenCL platform. Throws Error (device) when there is no platform, with
// the package to install.
std::vector<DeviceInfo> list_devices();

} // namespace lasmesh
