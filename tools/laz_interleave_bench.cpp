// SPDX-License-Identifier: Apache-2.0
// Whether decoding two LAZ streams symbol by symbol, in turn, would speed a core up: times
// ArithmeticDecoder::decode_symbol over two independent streams, one after the other and then
// alternating. If a decoder were held back by the latency of its chain (each symbol waits for the
// previous one's interval and value), the alternating loop would run up to twice as fast; if it
// is held back by its instructions, no faster. Two kinds of stream: random bytes (the symbols are
// unpredictable: the first guess at the likely symbol misses) and zero bytes (always the same
// symbol: the guess always hits). Best of 3, nanoseconds a symbol.
// Usage: laz_interleave_bench
#include "read/arithmetic_decoder.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <random>
#include <utility>
#include <vector>

using lasmesh::laz::ArithmeticDecoder;
using lasmesh::laz::ModelStore;
using lasmesh::laz::SymbolModel;

namespace {

constexpr int symbols_per_stream = 4'000'000;

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Nanoseconds a symbol: {one stream after the other, the two in turn}.
std::pair<double, double> time_decoding(const std::vector<std::byte>& a, const std::vector<std::byte>& b,
                                        std::uint32_t symbols, std::uint32_t& sink) {
    ModelStore store;
    ArithmeticDecoder da(a, store), db(b, store);
    SymbolModel ma(symbols, store), mb(symbols, store);
    auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < symbols_per_stream; ++i) sink += da.decode_symbol(ma);
    for (int i = 0; i < symbols_per_stream; ++i) sink += db.decode_symbol(mb);
    const double one_after_other = seconds_since(start);
    ArithmeticDecoder ea(a, store), eb(b, store);
    SymbolModel na(symbols, store), nb(symbols, store);
    start = std::chrono::steady_clock::now();
    for (int i = 0; i < symbols_per_stream; ++i) sink += ea.decode_symbol(na) + eb.decode_symbol(nb);
    const double in_turn = seconds_since(start);
    const double per_symbol = 1e9 / (2.0 * symbols_per_stream);
    return {one_after_other * per_symbol, in_turn * per_symbol};
}

} // namespace

int main() {
    const std::size_t bytes = 8u << 20; // more than 4M symbols take (reading past the end gives zeros)
    std::mt19937 random(1);
    std::vector<std::byte> random_a(bytes), random_b(bytes), zeros(bytes, std::byte{0});
    for (std::byte& x : random_a) x = std::byte(random() & 0xFF);
    for (std::byte& x : random_b) x = std::byte(random() & 0xFF);
    std::uint32_t sink = 0; // printed, so the decoding is not optimised away
    std::printf("| stream | model symbols | one after the other, ns/symbol | in turn, ns/symbol | speed-up "
                "|\n|---|---|---|---|---|\n");
    for (const bool predictable : {false, true}) {
        for (const std::uint32_t symbols : {4u, 64u, 256u}) {
            double best_sequential = 1e300, best_in_turn = 1e300;
            for (int round = 0; round < 3; ++round) {
                const auto [sequential, in_turn] = predictable ? time_decoding(zeros, zeros, symbols, sink)
                                                               : time_decoding(random_a, random_b, symbols, sink);
                best_sequential = std::min(best_sequential, sequential);
                best_in_turn = std::min(best_in_turn, in_turn);
            }
            std::printf("| %s | %u | %.2f | %.2f | %.2fx |\n", predictable ? "zero bytes" : "random bytes", symbols,
                        best_sequential, best_in_turn, best_sequential / best_in_turn);
        }
    }
    std::printf("(checksum %u)\n", sink);
}
