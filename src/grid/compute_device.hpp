// SPDX-License-Identifier: Apache-2.0
// The OpenCL device that accumulates the grid: listed, chosen, and opened once per run.
// PoCL on the CPU works everywhere; a GPU is preferred when one is present.
#pragma once

#include "lasmesh/devices.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace lasmesh {

class ComputeDevice {
  public:
    // `selector`: "auto" (the first GPU, else the first device), an index from list_devices(),
    // or a case-insensitive part of a device name. Throws Error (device, or usage for a selector
    // that matches nothing).
    explicit ComputeDevice(const std::string& selector = "auto");
    ~ComputeDevice();
    ComputeDevice(const ComputeDevice&) = delete;
    ComputeDevice& operator=(const ComputeDevice&) = delete;

    const DeviceInfo& info() const;

    struct Impl; // OpenCL objects; defined in src/opencl_device.hpp for the stages that use them
    Impl& impl() { return *impl_; }

  private:
    std::unique_ptr<Impl> impl_;
};

} // namespace lasmesh
