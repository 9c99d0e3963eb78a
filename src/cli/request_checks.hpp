// SPDX-License-Identifier: Apache-2.0
// What `lasmesh view`'s server checks on every request before it answers (view_server.hpp):
// the URL's token and the Host header.
#pragma once

#include <string>

namespace lasmesh::cli {

// 128 random bits as 32 hex digits, from the kernel's random source.
std::string random_token();

// Whether `given` is `token`, compared in a time that does not depend on where they differ.
bool same_token(const std::string& given, const std::string& token);

// An IPv4 or IPv6 address in text ("192.168.1.5", "fe80::1"), not a name.
bool is_ip_address(const std::string& text);

// 127.0.0.1, ::1 or localhost.
bool is_loopback(const std::string& address);

// Whether the Host header `host` names a server on `port`: "127.0.0.1:8080", "localhost:8080",
// "[::1]:8080"; when `any_address` (listening on the network), also any IP address or `machine`
// (this machine's name). A name that is neither (a DNS name pointed at this machine by someone
// else's page) is refused, as is another port or none.
bool host_names_server(const std::string& host, int port, bool any_address, const std::string& machine);

} // namespace lasmesh::cli
