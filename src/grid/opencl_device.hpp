// SPDX-License-Identifier: Apache-2.0
// Internal: the OpenCL C++ bindings, configured once, and the objects behind ComputeDevice.
#pragma once

#define CL_HPP_TARGET_OPENCL_VERSION 120
#define CL_HPP_MINIMUM_OPENCL_VERSION 120
#define CL_HPP_ENABLE_EXCEPTIONS
#include <CL/opencl.hpp>

#include "grid/compute_device.hpp"

#include <string>

namespace lasmesh {

struct ComputeDevice::Impl {
    DeviceInfo info;
    cl::Device device;
    cl::Context context;
    cl::CommandQueue queue;
};

// Builds `source` for the device with `options` (-D flags); a failure throws Error (device) with
// the compiler's log.
cl::Program build_program(ComputeDevice::Impl& device, const char* name, const std::string& source,
                          const std::string& options);

// Turns an OpenCL exception into an Error (device) that says what failed and the error's name.
[[noreturn]] void throw_device_error(const cl::Error& error, const std::string& doing);

} // namespace lasmesh
