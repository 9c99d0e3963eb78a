// SPDX-License-Identifier: Apache-2.0
// A survey: the inputs of one run (a scan delivered as many files: one per station, flight line
// or tile) read as one stream of point records in one record layout and one fixed-point frame.
// The grid decides cells and sums positions in raw integers (kernels/accumulate.cl), so records
// of files with other scales or offsets are brought into the survey's frame on the host first;
// records of files that agree with it are handed out as they are, byte for byte. The frame, the
// layout and the bounds are chosen from the set of files, never from their order, so the sums,
// and the mesh, do not depend on the order of the inputs.
//
// Files in another coordinate system than the survey's are transformed with PROJ on the way, and
// a survey in longitude and latitude is meshed in the UTM zone of its centre: cells are cubes in
// one unit only in a projected CRS.
//
// Memory: one file is open at a time, or one batch of small compressed files decoded together
// (read/decode_ahead.hpp, at most 32 MiB), and each file costs a SurveyFile (a path and a few
// numbers), so 10,000 small files cost about what one large one does.
#pragma once

#include "lasmesh/las_reader.hpp"
#include "lasmesh/mesh.hpp"
#include "read/crs.hpp"
#include "read/crs_transform.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace lasmesh {

// What a run keeps of one input's header while it reads the others.
struct SurveyFile {
    std::string path;
    std::uint64_t point_count = 0;
    std::uint8_t point_format = 0;
    std::uint16_t record_length = 0;
    Vec3 record_scale{}, record_offset{}; // what the file's raw integers mean, in its own CRS
    // In the survey's CRS: the file's bounds, and the scale and offset it would have there (its
    // own, unless it is transformed: then a thousandth of the unit, and whole units).
    Vec3 scale{}, offset{}, min{}, max{};
    std::shared_ptr<const CrsTransform> transform; // from the file's CRS to the survey's; null: none
    std::uint64_t bytes = 0; // the file's size (compressed size for a compressed stream), for progress
    bool compressed = false; // LAZ, or a gzip/bzip2/xz/zstd stream: reading it is CPU work
    // Read only the LAZ chunks that start at these offsets (a tile's COPC nodes), which hold
    // chunk_points points; empty: all.
    std::vector<std::uint64_t> chunks;
    std::uint64_t chunk_points = 0;
};

// An input left out (with skip_bad), and why: the error it gave.
struct SkippedInput {
    std::string path, reason;
};

struct Survey {
    std::vector<SurveyFile> files; // in the order given, those with points and those without
    std::vector<SkippedInput> skipped;
    // The records as SurveyReader hands them out: the point format and record length shared by
    // every file (else format 2, or 0 when no file has colour, holding only X, Y, Z and colour),
    // the frame's scale and offset, the union of the files' bounds, the total count.
    LasHeader header;
    // The CRS the mesh is in: the one most files declare (the same whatever their order), the one
    // asked for, or the UTM zone of a survey in longitude and latitude. Files that declare none
    // are taken to be in it (said in `notes`). Empty when neither the files nor the user name one.
    std::optional<CrsInfo> crs;
    std::string crs_line;           // for the summary: the CRS, and where it came from
    std::vector<std::string> notes; // "note: ..." and "warning: ..." lines for the run's warnings
};

struct SurveyOptions {
    bool skip_bad = false;    // leave out a file that cannot be read (listed in `skipped`)
    bool check_bounds = true; // refuse headers whose bounds are damaged (false: bounds given, or scanned)
    std::string crs;          // the CRS to mesh in ("EPSG:32631", a WKT); empty: the files'
};

// Reads the header of every input and chooses the CRS, the frame and the layout. With several
// inputs "-" is refused (each file is opened twice, header first); `open_first`, when given, is
// paths[0] already open (one input: standard input too), used instead of opening it. Throws
// Error (input) naming the file that cannot be read or transformed; with options.skip_bad, a file
// that cannot be read is left out and listed in `skipped` instead (none left is still an error).
Survey read_survey(const std::vector<std::string>& paths, const SurveyOptions& options,
                   LasReader* open_first = nullptr);

// An Error's option with skip_bad_inputs added: a bad file of several can be left out.
std::string with_skip_option(const std::string& option);

// The survey without files[index] (a file that failed while its points were read): the frame,
// layout and bounds chosen again from the others, as if it had never been given.
Survey survey_without(const Survey& survey, std::size_t index, const std::string& reason);

// The survey's header as the files' own headers give it: the frame, layout, bounds and count
// chosen from `files` (and the CRS fields left as they are).
void choose_frame(Survey& survey);

struct DecodedFile; // read/decode_ahead.hpp

// The records of one input as they are (a LasReader already open), or of every file of a survey
// one after the other, in the survey's CRS, frame and layout.
class SurveyReader {
  public:
    explicit SurveyReader(LasReader& single);
    // `open_first`: the survey's first file, already open (read_survey's).
    explicit SurveyReader(const Survey& survey, LasReader* open_first = nullptr);
    ~SurveyReader();

    const LasHeader& header() const { return *header_; }
    const std::string& name() const { return name_; } // the input's name, or "64 files"
    std::uint64_t records_left() const { return header_->point_count - records_read_; }

    // Fills `dst` with up to dst.size() / record length whole records, going on into the next
    // file as each ends; 0 once every record is read. Throws Error (input) as LasReader does,
    // naming the file; failed_file() then says which.
    std::size_t read_records(std::span<std::byte> dst);

    // The bytes read so far and in all (compressed bytes for compressed streams), for progress.
    std::uint64_t bytes_read() const;
    std::optional<std::uint64_t> bytes_total() const;
    // The warnings of the files read to their end: records past the header's count and the like.
    const std::vector<std::string>& warnings() const { return warnings_; }
    // The index in the survey's files of the file whose read threw; nullopt for a single input.
    std::optional<std::size_t> failed_file() const { return failed_; }
    // The file each of warnings() is about (a survey's reader only).
    const std::vector<std::size_t>& warning_files() const { return warning_files_; }
    // Called with each run of records of one file as it is handed out, in the survey's frame and
    // layout (a survey's reader only); returns how many to hand out, moved to the front of the
    // run: a tile job checks where they lie and keeps its tile's (tile_job.cpp).
    using RecordsSeen = std::function<std::size_t(std::size_t file, std::byte* records, std::size_t count)>;
    void on_records(RecordsSeen seen) { seen_ = std::move(seen); }

  private:
    void open_next();
    void finish_current();
    std::uint64_t current_left() const;
    std::size_t read_current(std::span<std::byte> dst);
    void convert_positions(std::byte* records, std::size_t count, std::size_t stride, const SurveyFile& file);

    LasReader* single_ = nullptr;
    const Survey* survey_ = nullptr;
    const LasHeader* header_ = nullptr;
    std::string name_;
    LasReader* open_first_ = nullptr;
    LasReader* current_ = nullptr;
    std::unique_ptr<LasReader> opened_; // current_ when this reader opened it
    // Or the current file decoded ahead, one of a batch of files [batch_first_, batch_first_ +
    // batch_.size()), and how many of its records are handed out.
    std::vector<DecodedFile> batch_;
    std::size_t batch_first_ = 0;
    DecodedFile* decoded_ = nullptr;
    std::uint64_t decoded_read_ = 0;
    std::vector<double> x_, y_, z_; // a batch of positions for PROJ
    std::size_t next_ = 0;          // the survey's next file to open
    std::uint64_t records_read_ = 0, bytes_done_ = 0;
    std::vector<std::byte> scratch_; // a file's records before they are brought into the layout
    std::vector<std::string> warnings_;
    std::vector<std::size_t> warning_files_;
    std::optional<std::size_t> failed_;
    RecordsSeen seen_;
};

} // namespace lasmesh
