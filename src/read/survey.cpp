// SPDX-License-Identifier: Apache-2.0
// Survey: the headers first (frame, layout, bounds, CRS), then the records file after file,
// brought into the survey's frame where a file's scale or offset differs.
#include "read/survey.hpp"

#include "byte_order.hpp"
#include "lasmesh/error.hpp"
#include "read/input_stream.hpp"
#include "read/las_header.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

namespace lasmesh {

namespace {

constexpr double int32_lowest = std::numeric_limits<std::int32_t>::min();
constexpr double int32_highest = std::numeric_limits<std::int32_t>::max();

// Files of one survey repeat the same CRS VLRs, and PROJ takes a context to read one: each
// distinct declaration is read once. The key is what read_crs reads: the WKT bit and the VLRs.
std::string crs_key(const LasHeader& h) {
    std::string key(1, static_cast<char>(h.global_encoding >> 4 & 1));
    for (const Vlr& vlr : h.vlrs) {
        if (vlr.user_id != "LASF_Projection") continue;
        key += std::to_string(vlr.record_id) + ":" + std::to_string(vlr.data.size()) + ":";
        key.append(reinterpret_cast<const char*>(vlr.data.data()), vlr.data.size());
    }
    return key;
}

// The CRS as the outputs would record it, or as people read it when PROJ cannot identify it.
std::string crs_identity(const CrsInfo& crs) {
    return crs.identified() ? crs_for_outputs(crs) : crs_summary(crs);
}

bool frame_fits(double min, double max, double scale, double offset) {
    return (min - offset) / scale >= int32_lowest + 1 && (max - offset) / scale <= int32_highest - 1;
}

} // namespace

std::string with_skip_option(const std::string& option) {
    return option.empty() ? "skip_bad_inputs" : option + ",skip_bad_inputs";
}

void choose_frame(Survey& survey) {
    LasHeader& h = survey.header;
    h = LasHeader{};
    h.version_major = 1, h.version_minor = 2;
    std::vector<const SurveyFile*> with_points;
    for (const SurveyFile& file : survey.files) {
        h.point_count += file.point_count;
        if (file.point_count > 0) with_points.push_back(&file);
    }
    h.point_format = 0;
    h.point_record_length = core_record_size(0);
    h.scale = {0.001, 0.001, 0.001};
    if (with_points.empty()) return;
    const SurveyFile& any = *with_points.front(); // where all agree, any file's value is theirs
    bool same_layout = true, same_frame = true, color = false;
    h.min = any.min, h.max = any.max;
    for (const SurveyFile* file : with_points) {
        same_layout = same_layout && file->point_format == any.point_format && file->record_length == any.record_length;
        same_frame = same_frame && file->scale == any.scale && file->offset == any.offset;
        color = color || rgb_offset(file->point_format) >= 0;
        for (int a = 0; a < 3; ++a) {
            h.min[a] = std::min(h.min[a], file->min[a]);
            h.max[a] = std::max(h.max[a], file->max[a]);
        }
    }
    if (same_layout) {
        h.point_format = any.point_format;
        h.point_record_length = any.record_length;
    } else { // X, Y, Z and colour are all the grid reads: the smallest format that holds them
        h.point_format = color ? 2 : 0;
        h.point_record_length = core_record_size(h.point_format);
    }
    if (same_frame) {
        h.scale = any.scale, h.offset = any.offset;
        return;
    }
    // The finest scale of any file keeps every file's resolution; the smallest offset is one a
    // writer chose (often a round number). Where the union does not fit 32-bit integers around
    // it, the union's centre; where it does not fit at that scale, a coarser scale.
    for (int a = 0; a < 3; ++a) {
        double scale = any.scale[a], offset = any.offset[a];
        for (const SurveyFile* file : with_points) {
            scale = std::min(scale, file->scale[a]);
            offset = std::min(offset, file->offset[a]);
        }
        if (!frame_fits(h.min[a], h.max[a], scale, offset))
            offset = std::round((h.min[a] + h.max[a]) / 2 / scale) * scale;
        while (!frame_fits(h.min[a], h.max[a], scale, offset)) {
            scale *= 10;
            offset = std::round((h.min[a] + h.max[a]) / 2 / scale) * scale;
        }
        h.scale[a] = scale, h.offset[a] = offset;
    }
}

Survey read_survey(const std::vector<std::string>& paths, bool skip_bad, bool check_bounds) {
    Survey survey;
    std::map<std::string, std::optional<CrsInfo>> crs_read; // by crs_key
    std::string crs_from;                                   // the first file that declares the CRS
    std::vector<std::string> without_crs;
    std::optional<Error> conflict;
    for (const std::string& path : paths) {
        if (path == "-")
            throw Error(ErrorKind::usage,
                        "standard input (-) must be the only input: with several inputs each is read twice, "
                        "its header first, and a pipe can be read once",
                        "inputs");
        try {
            LasReader reader(path);
            const LasHeader& h = reader.header();
            const std::string& name = reader.stream().name();
            if (check_bounds && h.point_count > 0) check_header_bounds_usable(h, name);
            const std::string key = crs_key(h);
            auto known = crs_read.find(key);
            if (known == crs_read.end()) known = crs_read.emplace(key, read_crs(h)).first;
            const std::optional<CrsInfo>& crs = known->second;
            if (!crs) {
                without_crs.push_back(name);
            } else if (!survey.crs) {
                survey.crs = crs, crs_from = name;
            } else if (crs_identity(*crs) != crs_identity(*survey.crs)) {
                conflict = Error(ErrorKind::input, name + " declares the coordinate system " + crs_summary(*crs) +
                                                       ", but " + crs_from + " declares " + crs_summary(*survey.crs) +
                                                       ": the inputs of one mesh must share one coordinate system; "
                                                       "reproject one of them first (nothing was written)");
                break;
            }
            SurveyFile file;
            file.path = path;
            file.point_count = h.point_count;
            file.point_format = h.point_format;
            file.record_length = h.point_record_length;
            file.scale = h.scale, file.offset = h.offset, file.min = h.min, file.max = h.max;
            file.bytes = reader.stream().raw_size().value_or(0);
            survey.files.push_back(std::move(file));
        } catch (const Error& e) {
            if (e.kind() != ErrorKind::input) throw;
            if (!skip_bad) throw Error(e.kind(), e.what(), with_skip_option(e.option()), e.suggestion());
            survey.skipped.push_back({path, e.what()});
        }
    }
    if (conflict) throw *conflict; // not a bad file, and never skipped: which CRS is wanted?
    if (survey.files.empty())
        throw Error(ErrorKind::input,
                    "none of the " + std::to_string(paths.size()) +
                        " inputs could be read: " + survey.skipped.front().reason,
                    "inputs");
    if (survey.crs && !without_crs.empty())
        survey.notes.push_back("note: " + std::to_string(without_crs.size()) + " of the inputs (" +
                               without_crs.front() + (without_crs.size() > 1 ? " and others" : "") +
                               ") declare no coordinate system: taken to be in " + crs_identity(*survey.crs) +
                               " like " + crs_from);
    choose_frame(survey);
    return survey;
}

Survey survey_without(const Survey& survey, std::size_t index, const std::string& reason) {
    Survey rest = survey;
    rest.skipped.push_back({survey.files[index].path, reason});
    rest.files.erase(rest.files.begin() + static_cast<std::ptrdiff_t>(index));
    if (rest.files.empty())
        throw Error(ErrorKind::input, "no input is left once " + survey.files[index].path + " is left out: " + reason,
                    "inputs");
    choose_frame(rest);
    return rest;
}

// How a file's raw integers on one axis become the survey's: raw * step + shift exactly when the
// file's scale is a whole multiple of the survey's and the offsets differ by whole steps (the
// usual case: the same scale, offsets on round numbers), else through the coordinate, rounded.
struct AxisMap {
    bool identity = true, exact = true;
    std::int64_t step = 1, shift = 0;
    double scale = 1, offset_difference = 0, survey_scale = 1;

    AxisMap() = default;
    AxisMap(double file_scale, double file_offset, double survey_scale_, double survey_offset)
        : scale(file_scale), offset_difference(file_offset - survey_offset), survey_scale(survey_scale_) {
        identity = file_scale == survey_scale_ && file_offset == survey_offset;
        const double ratio = file_scale / survey_scale, steps = offset_difference / survey_scale;
        exact = std::abs(ratio - std::round(ratio)) < 1e-9 * ratio && std::abs(steps - std::round(steps)) < 1e-6 &&
                std::abs(steps) < 1e15;
        step = static_cast<std::int64_t>(std::round(ratio));
        shift = exact ? static_cast<std::int64_t>(std::round(steps)) : 0;
    }
    // Clamped to 32 bits: a point that far beyond the header's bounds lies outside the grid anyway.
    std::int32_t operator()(std::int32_t raw) const {
        if (identity) return raw;
        const double value = exact ? static_cast<double>(raw * step + shift)
                                   : std::round((raw * scale + offset_difference) / survey_scale);
        return static_cast<std::int32_t>(std::clamp(value, int32_lowest, int32_highest));
    }
};

SurveyReader::SurveyReader(LasReader& single)
    : single_(&single), header_(&single.header()), name_(single.stream().name()) {}

SurveyReader::SurveyReader(const Survey& survey) : survey_(&survey), header_(&survey.header) {
    name_ = survey.files.size() == 1 ? survey.files.front().path : std::to_string(survey.files.size()) + " files";
}

SurveyReader::~SurveyReader() = default;

std::uint64_t SurveyReader::bytes_read() const {
    if (single_) return single_->stream().raw_position();
    return bytes_done_ + (current_ ? current_->stream().raw_position() : 0);
}

std::optional<std::uint64_t> SurveyReader::bytes_total() const {
    if (single_) return single_->stream().raw_size();
    std::uint64_t total = 0;
    for (const SurveyFile& file : survey_->files) total += file.bytes;
    return total;
}

void SurveyReader::open_next() {
    while (survey_->files[next_].point_count == 0) bytes_done_ += survey_->files[next_++].bytes;
    const SurveyFile& file = survey_->files[next_++];
    current_ = std::make_unique<LasReader>(file.path);
    const LasHeader& h = current_->header();
    if (h.point_count != file.point_count || h.point_format != file.point_format || h.scale != file.scale ||
        h.offset != file.offset || h.min != file.min || h.max != file.max)
        throw_input_error(current_->stream().name(), "its header changed between the first look at it and its "
                                                     "points being read (is it being written?)");
}

void SurveyReader::finish_current() {
    if (std::string warning = trailing_warning(*current_); !warning.empty()) warnings_.push_back(std::move(warning));
    bytes_done_ += survey_->files[next_ - 1].bytes;
    current_.reset();
}

std::size_t SurveyReader::read_records(std::span<std::byte> dst) {
    if (single_) {
        const bool was_open = single_->records_left() > 0;
        const std::size_t n = single_->read_records(dst);
        records_read_ += n;
        if (was_open && single_->records_left() == 0)
            if (std::string warning = trailing_warning(*single_); !warning.empty()) warnings_.push_back(warning);
        return n;
    }
    const std::size_t length = header_->point_record_length;
    const int survey_rgb = rgb_offset(header_->point_format);
    const std::size_t capacity = dst.size() / length;
    std::size_t total = 0;
    try {
        while (total < capacity && records_left() > 0) {
            if (!current_) open_next();
            const SurveyFile& file = survey_->files[next_ - 1];
            const std::array<AxisMap, 3> map{
                AxisMap(file.scale[0], file.offset[0], header_->scale[0], header_->offset[0]),
                AxisMap(file.scale[1], file.offset[1], header_->scale[1], header_->offset[1]),
                AxisMap(file.scale[2], file.offset[2], header_->scale[2], header_->offset[2])};
            const bool same_frame = map[0].identity && map[1].identity && map[2].identity;
            const std::size_t wanted =
                static_cast<std::size_t>(std::min<std::uint64_t>(capacity - total, current_->records_left()));
            std::byte* out = dst.data() + total * length;
            std::size_t got = 0;
            if (file.point_format == header_->point_format && file.record_length == length) {
                got = current_->read_records({out, wanted * length});
                if (!same_frame)
                    for (std::size_t i = 0; i < got; ++i)
                        for (int a = 0; a < 3; ++a) {
                            std::byte* at = out + i * length + 4 * a;
                            store_le<std::int32_t>(at, map[a](load_le<std::int32_t>(at)));
                        }
            } else { // into the survey's layout: X, Y, Z, then colour where the survey has it
                scratch_.resize(wanted * file.record_length);
                got = current_->read_records(scratch_);
                const int file_rgb = rgb_offset(file.point_format);
                std::memset(out, 0, got * length);
                for (std::size_t i = 0; i < got; ++i) {
                    const std::byte* from = scratch_.data() + i * file.record_length;
                    std::byte* to = out + i * length;
                    for (int a = 0; a < 3; ++a)
                        store_le<std::int32_t>(to + 4 * a, map[a](load_le<std::int32_t>(from + 4 * a)));
                    if (survey_rgb >= 0 && file_rgb >= 0) std::memcpy(to + survey_rgb, from + file_rgb, 6);
                }
            }
            total += got;
            records_read_ += got;
            if (got == 0 || current_->records_left() == 0) finish_current();
        }
    } catch (const Error&) {
        failed_ = next_ - 1;
        throw;
    }
    return total;
}

} // namespace lasmesh
