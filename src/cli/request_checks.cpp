// SPDX-License-Identifier: Apache-2.0
#include "request_checks.hpp"

#include <arpa/inet.h>

#include <cstdio>
#include <random>

namespace lasmesh::cli {

// std::random_device reads the kernel's getrandom on Linux.
std::string random_token() {
    std::random_device random;
    std::string token;
    char digits[9];
    for (int i = 0; i < 4; ++i) {
        std::snprintf(digits, sizeof digits, "%08x", static_cast<unsigned>(random()));
        token += digits;
    }
    return token;
}

// A guess learns nothing from the timing.
bool same_token(const std::string& given, const std::string& token) {
    if (given.size() != token.size()) return false;
    unsigned char differ = 0;
    for (std::size_t i = 0; i < token.size(); ++i) differ |= static_cast<unsigned char>(given[i] ^ token[i]);
    return differ == 0;
}

bool is_ip_address(const std::string& text) {
    unsigned char bytes[16];
    return inet_pton(AF_INET, text.c_str(), bytes) == 1 || inet_pton(AF_INET6, text.c_str(), bytes) == 1;
}

bool is_loopback(const std::string& address) {
    return address == "127.0.0.1" || address == "::1" || address == "localhost";
}

bool host_names_server(const std::string& host, int port, bool any_address, const std::string& machine) {
    const std::size_t colon = host.rfind(':');
    if (colon == std::string::npos || colon == 0 || host.substr(colon + 1) != std::to_string(port)) return false;
    std::string name = host.substr(0, colon);
    if (name.front() == '[') { // an IPv6 address
        if (name.back() != ']') return false;
        name = name.substr(1, name.size() - 2);
        if (!is_ip_address(name)) return false;
    }
    if (is_loopback(name)) return true;
    return any_address && (is_ip_address(name) || (!machine.empty() && name == machine));
}

} // namespace lasmesh::cli
