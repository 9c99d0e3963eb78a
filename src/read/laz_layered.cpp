#include "read/laz_layered.hpp"
namespace lasmesh::laz {
void decode_layered_chunk(const Format&, std::span<const std::byte>, std::uint64_t, std::byte*) {
    throw ChunkError(0, "layered chunks are not decoded yet");
}
}
