// SPDX-License-Identifier: Apache-2.0
// Small compressed files of a survey decoded several at once. Reading LAZ or a gzip, bzip2, xz or
// zstd stream is CPU work; a large LAZ file decodes its chunks in parallel (LazDecoder), but a
// file of one or two chunks keeps one core busy while the others wait. A survey of many such
// files (one per scanner station, flight line or tile) is therefore read a batch at a time, each
// file of a batch decoded whole on a thread of its own, and handed out in the survey's order:
// the records, and the sums, are those of reading the files one after the other.
//
// Memory: a batch holds at most batch_bytes of decoded records (and each of its files at most
// small_file_bytes); larger files are read as a stream, as before.
#pragma once

#include "lasmesh/las_reader.hpp"
#include "read/survey.hpp"

#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <string>
#include <vector>

namespace lasmesh {

inline constexpr std::uint64_t small_file_bytes = std::uint64_t{8} << 20;
inline constexpr std::uint64_t batch_bytes = std::uint64_t{32} << 20;

// One file of a batch, decoded.
struct DecodedFile {
    std::vector<std::byte> records; // every record, as LasReader hands them out
    std::string warning;            // what trailing_warning says at its end; empty: nothing
    std::exception_ptr error;       // why it could not be read: thrown when its turn comes
};

// `file` opened again for its points (only its `chunks`, when it lists some); throws Error (input)
// when its header is no longer the one read_survey saw.
std::unique_ptr<LasReader> reopen(const SurveyFile& file);
// `reader` set to read only `file`'s chunks; throws Error (input) when they do not hold its chunk_points.
void read_only_chunks(LasReader& reader, const SurveyFile& file);

// How many files from files[first] on one batch takes: the run of small compressed files (files
// without points included) that fits batch_bytes. Below 2 the next file is read on its own.
std::size_t batch_length(const std::vector<SurveyFile>& files, std::size_t first);

// files[first, first + count) decoded, in parallel (TBB), one entry each.
std::vector<DecodedFile> decode_batch(const std::vector<SurveyFile>& files, std::size_t first, std::size_t count);

} // namespace lasmesh
