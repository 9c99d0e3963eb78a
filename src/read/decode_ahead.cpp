// SPDX-License-Identifier: Apache-2.0
#include "read/decode_ahead.hpp"

#include "lasmesh/error.hpp"
#include "read/input_stream.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace lasmesh {

void read_only_chunks(LasReader& reader, const SurveyFile& file) {
    reader.read_only_chunks(file.chunks);
    if (reader.header().point_count != file.chunk_points)
        throw_input_error(reader.stream().name(),
                          "its " + std::to_string(file.chunks.size()) + " LAZ chunks to read hold " +
                              std::to_string(reader.header().point_count) + " points, not the " +
                              std::to_string(file.chunk_points) + " its COPC hierarchy gave when planned: plan again");
}

std::unique_ptr<LasReader> reopen(const SurveyFile& file) {
    auto reader = std::make_unique<LasReader>(file.path);
    const LasHeader& h = reader->header();
    if (h.point_count != file.point_count || h.point_format != file.point_format || h.scale != file.record_scale ||
        h.offset != file.record_offset)
        throw_input_error(reader->stream().name(), "its header changed between the first look at it and its "
                                                   "points being read (is it being written?)");
    if (!file.chunks.empty()) read_only_chunks(*reader, file);
    return reader;
}

std::size_t batch_length(const std::vector<SurveyFile>& files, std::size_t first) {
    // As many files as threads: a batch takes about one file's time, and the device works on the
    // slices read before it meanwhile.
    const auto threads = static_cast<std::size_t>(tbb::this_task_arena::max_concurrency());
    if (threads < 2) return 0;
    std::uint64_t bytes = 0;
    std::size_t end = first, with_points = 0;
    for (; end < files.size() && with_points < threads; ++end) {
        const SurveyFile& file = files[end];
        const std::uint64_t records = file.point_count * file.record_length;
        if (file.point_count > 0 && (!file.compressed || records > small_file_bytes)) break;
        if (bytes + records > batch_bytes) break;
        bytes += records;
        with_points += file.point_count > 0;
    }
    return end - first;
}

std::vector<DecodedFile> decode_batch(const std::vector<SurveyFile>& files, std::size_t first, std::size_t count) {
    std::vector<DecodedFile> decoded(count);
    tbb::parallel_for(std::size_t{0}, count, [&](std::size_t i) {
        const SurveyFile& file = files[first + i];
        if (file.point_count == 0) return;
        try {
            const std::unique_ptr<LasReader> reader = reopen(file);
            decoded[i].records.resize(reader->header().point_count * file.record_length);
            reader->read_records(decoded[i].records); // the whole file: LasReader throws when it holds fewer
            decoded[i].warning = trailing_warning(*reader);
        } catch (...) {
            decoded[i].records = {};
            decoded[i].error = std::current_exception();
        }
    });
    return decoded;
}

} // namespace lasmesh
