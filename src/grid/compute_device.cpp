// SPDX-License-Identifier: Apache-2.0
// Device discovery and selection through the OpenCL ICD loader, and kernel builds with logs.
#include "opencl_device.hpp"

#include "grid/compiler_pages.hpp"
#include "lasmesh/error.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>

namespace lasmesh {

namespace {

const char* error_name(cl_int code) {
    switch (code) {
    case CL_DEVICE_NOT_FOUND: return "CL_DEVICE_NOT_FOUND";
    case CL_MEM_OBJECT_ALLOCATION_FAILURE: return "CL_MEM_OBJECT_ALLOCATION_FAILURE";
    case CL_OUT_OF_RESOURCES: return "CL_OUT_OF_RESOURCES";
    case CL_OUT_OF_HOST_MEMORY: return "CL_OUT_OF_HOST_MEMORY";
    case CL_BUILD_PROGRAM_FAILURE: return "CL_BUILD_PROGRAM_FAILURE";
    case CL_INVALID_VALUE: return "CL_INVALID_VALUE";
    case CL_INVALID_BUFFER_SIZE: return "CL_INVALID_BUFFER_SIZE";
    case CL_INVALID_WORK_GROUP_SIZE: return "CL_INVALID_WORK_GROUP_SIZE";
    case CL_INVALID_KERNEL_ARGS: return "CL_INVALID_KERNEL_ARGS";
    case -1001: return "CL_PLATFORM_NOT_FOUND_KHR";
    default: return "OpenCL error";
    }
}

std::string lower(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
    return text;
}

const char* no_platform_help =
    "no OpenCL platform found: install one, e.g. `apt-get install pocl-opencl-icd` for the CPU, or "
    "your GPU vendor's OpenCL driver (an ICD under /etc/OpenCL/vendors)";

std::vector<std::pair<DeviceInfo, cl::Device>> all_devices() {
    std::vector<cl::Platform> platforms;
    try {
        cl::Platform::get(&platforms);
    } catch (const cl::Error&) {
        throw Error(ErrorKind::device, no_platform_help);
    }
    if (platforms.empty()) throw Error(ErrorKind::device, no_platform_help);
    std::vector<std::pair<DeviceInfo, cl::Device>> found;
    for (const cl::Platform& platform : platforms) {
        std::vector<cl::Device> devices;
        try {
            platform.getDevices(CL_DEVICE_TYPE_ALL, &devices);
        } catch (const cl::Error&) {
            continue; // a platform without devices (CL_DEVICE_NOT_FOUND)
        }
        for (const cl::Device& device : devices) {
            DeviceInfo info;
            info.index = static_cast<int>(found.size());
            info.platform = platform.getInfo<CL_PLATFORM_NAME>();
            info.name = device.getInfo<CL_DEVICE_NAME>();
            const cl_device_type type = device.getInfo<CL_DEVICE_TYPE>();
            info.type = type & CL_DEVICE_TYPE_GPU           ? "GPU"
                        : type & CL_DEVICE_TYPE_CPU         ? "CPU"
                        : type & CL_DEVICE_TYPE_ACCELERATOR ? "accelerator"
                                                            : "other";
            info.version = device.getInfo<CL_DEVICE_VERSION>();
            info.global_memory = device.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
            info.max_alloc = device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
            // Strip the NUL some drivers leave at the end of info strings.
            for (std::string* s : {&info.platform, &info.name, &info.version})
                while (!s->empty() && s->back() == '\0') s->pop_back();
            found.emplace_back(info, device);
        }
    }
    if (found.empty()) throw Error(ErrorKind::device, no_platform_help);
    return found;
}

} // namespace

[[noreturn]] void throw_device_error(const cl::Error& error, const std::string& doing) {
    throw Error(ErrorKind::device, "OpenCL failed while " + doing + ": " + error.what() + " returned " +
                                       error_name(error.err()) + " (" + std::to_string(error.err()) + ")");
}

std::vector<DeviceInfo> list_devices() {
    std::vector<DeviceInfo> infos;
    for (auto& [info, device] : all_devices()) infos.push_back(info);
    return infos;
}

ComputeDevice::ComputeDevice(const std::string& selector) : impl_(std::make_unique<Impl>()) {
    auto devices = all_devices();
    const std::pair<DeviceInfo, cl::Device>* chosen = nullptr;
    if (selector == "auto") {
        for (const auto& d : devices)
            if (d.first.type == "GPU") {
                chosen = &d;
                break;
            }
        if (!chosen) chosen = &devices.front();
    } else if (!selector.empty() && std::all_of(selector.begin(), selector.end(), ::isdigit)) {
        std::size_t index = 0; // digits too many for size_t leave it out of range, as any large index
        if (std::from_chars(selector.data(), selector.data() + selector.size(), index).ec != std::errc())
            index = SIZE_MAX;
        if (index >= devices.size())
            throw Error(ErrorKind::usage,
                        "device " + selector + ": there are " + std::to_string(devices.size()) + " devices", "device");
        chosen = &devices[index];
    } else {
        for (const auto& d : devices)
            if (lower(d.first.name).find(lower(selector)) != std::string::npos) {
                chosen = &d;
                break;
            }
        if (!chosen) throw Error(ErrorKind::usage, "device \"" + selector + "\": no device name contains it", "device");
    }
    impl_->info = chosen->first;
    impl_->device = chosen->second;
    try {
        impl_->context = cl::Context(impl_->device);
        impl_->queue = cl::CommandQueue(impl_->context, impl_->device);
    } catch (const cl::Error& e) {
        throw_device_error(e, "opening " + impl_->info.name);
    }
}

ComputeDevice::~ComputeDevice() = default;

const DeviceInfo& ComputeDevice::info() const {
    return impl_->info;
}

cl::Program build_program(ComputeDevice::Impl& device, const char* name, const std::string& source,
                          const std::string& options) {
    cl::Program program(device.context, source);
    try {
        program.build(std::vector<cl::Device>{device.device}, options.c_str());
    } catch (const cl::Error& e) {
        std::string log;
        try {
            log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device.device);
        } catch (const cl::Error&) {
        }
        if (e.err() == CL_BUILD_PROGRAM_FAILURE)
            throw Error(ErrorKind::device, std::string("kernel ") + name + " failed to build for " + device.info.name +
                                               " with options \"" + options + "\"; build log:\n" + log);
        throw_device_error(e, std::string("building kernel ") + name);
    }
    release_compiler_pages(); // built: the compiler's code need not stay resident (compiler_pages.hpp)
    return program;
}

} // namespace lasmesh
