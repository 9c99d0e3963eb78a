// SPDX-License-Identifier: Apache-2.0
// Survey: the headers first (frame, layout, bounds, CRS), then the records file after file,
// brought into the survey's frame where a file's scale or offset differs.
#include "read/survey.hpp"

#include "byte_order.hpp"
#include "lasmesh/error.hpp"
#include "read/decode_ahead.hpp"
#include "read/input_stream.hpp"
#include "read/las_header.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <limits>
#include <map>

namespace lasmesh {

namespace {

constexpr double int32_lowest = std::numeric_limits<std::int32_t>::min();
constexpr double int32_highest = std::numeric_limits<std::int32_t>::max();

// Files of one survey repeat the same CRS VLRs, and PROJ takes a context to read one: each
// distinct declaration is read once. The key is what read_crs reads: the WKT bit and the (E)VLRs.
std::string crs_key(const LasHeader& h) {
    std::string key(1, static_cast<char>(h.global_encoding >> 4 & 1));
    for (const std::vector<Vlr>* list : {&h.vlrs, &h.crs_evlrs})
        for (const Vlr& vlr : *list) {
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

namespace {

// x and y within longitude and latitude: a geographic CRS declared for coordinates that are not
// degrees (writers copy a CRS they did not use) is wrong, and is not used.
bool in_degrees(const Vec3& min, const Vec3& max) {
    return min[0] >= -180 && max[0] <= 360 && min[1] >= -90 && max[1] <= 90;
}

// The files' own CRSs, each distinct one once, and which each file declares.
struct DeclaredCrs {
    std::vector<CrsInfo> distinct;
    std::vector<std::string> first_file; // the first file declaring each
    std::vector<int> of_file;            // index in `distinct` per file; -1: none
    std::vector<std::string> without;    // files that declare none
};

// The CRS the mesh is in, and how each file gets there (see Survey::crs).
void choose_crs(Survey& survey, const DeclaredCrs& declared, const SurveyOptions& options) {
    std::optional<CrsInfo> target;
    std::string origin;
    if (!options.crs.empty()) {
        target = crs_from_text(options.crs);
        if (target->geographic())
            throw Error(ErrorKind::usage,
                        "the CRS asked for, " + options.crs + ", is " + crs_summary(*target) +
                            ": cells must be cubes in one unit, so give a projected CRS (in metres or feet)",
                        "crs");
        origin = " (asked for)";
    } else if (!declared.distinct.empty()) {
        // The CRS most files declare, the same whatever their order (a tie: the first by name).
        std::vector<std::size_t> count(declared.distinct.size());
        for (const int c : declared.of_file)
            if (c >= 0) ++count[static_cast<std::size_t>(c)];
        std::size_t best = 0;
        for (std::size_t c = 1; c < count.size(); ++c)
            if (count[c] > count[best] ||
                (count[c] == count[best] && crs_identity(declared.distinct[c]) < crs_identity(declared.distinct[best])))
                best = c;
        target = declared.distinct[best];
        if (target->geographic()) { // the UTM zone of the centre of the files in it
            std::optional<Bounds> all;
            for (std::size_t f = 0; f < survey.files.size(); ++f) {
                if (declared.of_file[f] != static_cast<int>(best) || survey.files[f].point_count == 0) continue;
                if (!all) all = Bounds{survey.files[f].min, survey.files[f].max};
                for (int a = 0; a < 2; ++a) {
                    all->min[a] = std::min(all->min[a], survey.files[f].min[a]);
                    all->max[a] = std::max(all->max[a], survey.files[f].max[a]);
                }
            }
            const Bounds centre_of = all.value_or(Bounds{});
            const CrsInfo geographic = *target;
            target = utm_crs_for(geographic, (centre_of.min[0] + centre_of.max[0]) / 2,
                                 (centre_of.min[1] + centre_of.max[1]) / 2);
            origin = " (projected from " + crs_summary(geographic) + ": the UTM zone of the data's centre)";
        }
    }
    if (!target) return;
    survey.crs = target;
    survey.crs_line = crs_summary(*target) + origin;
    if (!declared.without.empty())
        survey.notes.push_back("note: " + std::to_string(declared.without.size()) + " of the inputs (" +
                               declared.without.front() + (declared.without.size() > 1 ? " and others" : "") +
                               ") declare no coordinate system: taken to be in " + crs_identity(*target));
    if (target->unit_metres > 0 && target->vertical_unit_metres > 0 &&
        std::abs(target->vertical_unit_metres / target->unit_metres - 1) > 1e-6)
        survey.notes.push_back("warning: " + crs_summary(*target) + " measures heights in " + target->vertical_unit +
                               " and x and y in " + target->unit +
                               ": the cells are cubes in the file's numbers, not on the ground (ask for a CRS "
                               "whose units agree)");
    // Each file in another CRS: transformed, its bounds, scale and offset given in the target's.
    std::vector<std::shared_ptr<const CrsTransform>> transforms(declared.distinct.size());
    std::vector<std::string> transformed;
    for (std::size_t f = 0; f < survey.files.size(); ++f) {
        const int c = declared.of_file[f];
        if (c < 0 || crs_identity(declared.distinct[static_cast<std::size_t>(c)]) == crs_identity(*target)) continue;
        const CrsInfo& from = declared.distinct[static_cast<std::size_t>(c)];
        SurveyFile& file = survey.files[f];
        if (!from.identified())
            throw_input_error(file.path, "its coordinate system cannot be transformed to " + crs_summary(*target) +
                                             ": PROJ cannot read it (" + from.problem + ")");
        if (!transforms[static_cast<std::size_t>(c)])
            transforms[static_cast<std::size_t>(c)] = std::make_shared<const CrsTransform>(from, *target, file.path);
        file.transform = transforms[static_cast<std::size_t>(c)];
        transformed.push_back(file.path);
        if (file.point_count == 0) continue;
        const Bounds box = file.transform->bounds(Bounds{file.min, file.max});
        file.min = box.min, file.max = box.max;
        for (int a = 0; a < 3; ++a) file.scale[a] = 0.001, file.offset[a] = std::floor(file.min[a]);
    }
    if (!transformed.empty() && survey.files.size() > 1)
        survey.notes.push_back("note: " + std::to_string(transformed.size()) + " of the inputs (" +
                               transformed.front() + (transformed.size() > 1 ? " and others" : "") +
                               ") transformed into " + crs_identity(*target) + " with PROJ");
}

// A pipe (a FIFO, a process substitution, a terminal) gives its bytes once.
bool is_pipe(const std::string& path) {
    std::error_code failed;
    const std::filesystem::file_type type = std::filesystem::status(path, failed).type();
    return !failed && (type == std::filesystem::file_type::fifo || type == std::filesystem::file_type::character ||
                       type == std::filesystem::file_type::socket);
}

} // namespace

Survey read_survey(const std::vector<std::string>& paths, const SurveyOptions& options, LasReader* open_first) {
    Survey survey;
    DeclaredCrs declared;
    std::map<std::string, std::optional<CrsInfo>> crs_read; // by crs_key
    for (std::size_t i = 0; i < paths.size(); ++i) {
        const std::string& path = paths[i];
        if (path == "-" && paths.size() > 1)
            throw Error(ErrorKind::usage,
                        "standard input (-) must be the only input: with several inputs each is read twice, "
                        "its header first, and a pipe can be read once",
                        "inputs");
        // The same for any other pipe: opened again after its header was read, it would go on
        // from where the header ended and be "not a LAS file".
        if (paths.size() > 1 && !(i == 0 && open_first) && is_pipe(path))
            throw Error(ErrorKind::usage,
                        path + " is a pipe, not a file: with several inputs each is read twice, its header "
                               "first, and a pipe can be read once; save it to a file, or give it alone",
                        "inputs");
        try {
            std::unique_ptr<LasReader> opened;
            LasReader& reader = i == 0 && open_first ? *open_first : *(opened = std::make_unique<LasReader>(path));
            const LasHeader& h = reader.header();
            const std::string& name = reader.stream().name();
            if (options.check_bounds && h.point_count > 0) check_header_bounds_usable(h, name);
            const std::string key = crs_key(h);
            auto known = crs_read.find(key);
            if (known == crs_read.end()) known = crs_read.emplace(key, read_crs(h)).first;
            std::optional<CrsInfo> crs = known->second;
            if (crs && crs->geographic() && h.point_count > 0 && !in_degrees(h.min, h.max)) {
                survey.notes.push_back("warning: " + name + " declares " + crs_summary(*crs) +
                                       ", but its x and y are not longitudes and latitudes: the declaration is "
                                       "wrong, and is not used");
                crs.reset();
            }
            SurveyFile file;
            file.path = path;
            file.point_count = h.point_count;
            file.point_format = h.point_format;
            file.record_length = h.point_record_length;
            file.record_scale = file.scale = h.scale;
            file.record_offset = file.offset = h.offset;
            file.min = h.min, file.max = h.max;
            file.bytes = reader.stream().raw_size().value_or(0);
            file.compressed = h.compressed || reader.stream().compression() != Compression::none;
            survey.files.push_back(std::move(file));
            int index = -1;
            if (crs) {
                for (std::size_t c = 0; c < declared.distinct.size() && index < 0; ++c)
                    if (crs_identity(declared.distinct[c]) == crs_identity(*crs)) index = static_cast<int>(c);
                if (index < 0) {
                    index = static_cast<int>(declared.distinct.size());
                    declared.distinct.push_back(*crs);
                    declared.first_file.push_back(name);
                }
            } else {
                declared.without.push_back(name);
            }
            declared.of_file.push_back(index);
        } catch (const Error& e) {
            if (e.kind() != ErrorKind::input) throw;
            if (!options.skip_bad) throw Error(e.kind(), e.what(), with_skip_option(e.option()), e.suggestion());
            survey.skipped.push_back({path, e.what()});
        }
    }
    if (survey.files.empty())
        throw Error(ErrorKind::input,
                    "none of the " + std::to_string(paths.size()) +
                        " inputs could be read: " + survey.skipped.front().reason,
                    "inputs");
    choose_crs(survey, declared, options);
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

SurveyReader::SurveyReader(const Survey& survey, LasReader* open_first)
    : survey_(&survey), header_(&survey.header), open_first_(open_first) {
    name_ = survey.files.size() > 1 ? std::to_string(survey.files.size()) + " files"
            : open_first            ? open_first->stream().name()
                                    : survey.files.front().path;
}

SurveyReader::~SurveyReader() = default;

std::uint64_t SurveyReader::bytes_read() const {
    if (single_) return single_->stream().raw_position();
    return bytes_done_ + (current_ ? current_->stream().raw_position() : 0);
}

std::optional<std::uint64_t> SurveyReader::bytes_total() const {
    if (single_) return single_->stream().raw_size();
    if (open_first_ && survey_->files.size() == 1) return open_first_->stream().raw_size(); // a pipe: unknown
    std::uint64_t total = 0;
    for (const SurveyFile& file : survey_->files) total += file.bytes;
    return total;
}

void SurveyReader::open_next() {
    while (survey_->files[next_].point_count == 0) bytes_done_ += survey_->files[next_++].bytes;
    const std::size_t index = next_++;
    if (index == 0 && open_first_) {
        current_ = open_first_;
        return;
    }
    if (index >= batch_first_ + batch_.size()) {
        batch_.clear();
        if (const std::size_t count = batch_length(survey_->files, index); count >= 2) {
            batch_ = decode_batch(survey_->files, index, count);
            batch_first_ = index;
        }
    }
    if (index < batch_first_ + batch_.size()) {
        decoded_ = &batch_[index - batch_first_];
        decoded_read_ = 0;
        if (decoded_->error) std::rethrow_exception(decoded_->error);
        return;
    }
    opened_ = reopen(survey_->files[index]);
    current_ = opened_.get();
}

void SurveyReader::finish_current() {
    std::string warning = decoded_ ? std::move(decoded_->warning) : trailing_warning(*current_);
    if (!warning.empty()) warnings_.push_back(std::move(warning)), warning_files_.push_back(next_ - 1);
    bytes_done_ += survey_->files[next_ - 1].bytes;
    if (decoded_) std::vector<std::byte>().swap(decoded_->records);
    decoded_ = nullptr;
    current_ = nullptr;
    opened_.reset();
}

std::uint64_t SurveyReader::current_left() const {
    return decoded_ ? decoded_->records.size() / survey_->files[next_ - 1].record_length - decoded_read_
                    : current_->records_left();
}

std::size_t SurveyReader::read_current(std::span<std::byte> dst) {
    if (!decoded_) return current_->read_records(dst);
    const std::size_t length = survey_->files[next_ - 1].record_length;
    const std::size_t count = static_cast<std::size_t>(std::min<std::uint64_t>(dst.size() / length, current_left()));
    std::memcpy(dst.data(), decoded_->records.data() + decoded_read_ * length, count * length);
    decoded_read_ += count;
    return count;
}

// X, Y, Z of `count` records (`stride` bytes apart) from the file's raw integers to the survey's:
// as they are, through the frame (AxisMap), or through the coordinates and PROJ.
void SurveyReader::convert_positions(std::byte* records, std::size_t count, std::size_t stride,
                                     const SurveyFile& file) {
    const LasHeader& h = *header_;
    if (!file.transform) {
        const std::array<AxisMap, 3> map{AxisMap(file.record_scale[0], file.record_offset[0], h.scale[0], h.offset[0]),
                                         AxisMap(file.record_scale[1], file.record_offset[1], h.scale[1], h.offset[1]),
                                         AxisMap(file.record_scale[2], file.record_offset[2], h.scale[2], h.offset[2])};
        if (map[0].identity && map[1].identity && map[2].identity) return;
        for (std::size_t i = 0; i < count; ++i)
            for (int a = 0; a < 3; ++a) {
                std::byte* at = records + i * stride + 4 * a;
                store_le<std::int32_t>(at, map[a](load_le<std::int32_t>(at)));
            }
        return;
    }
    x_.resize(count), y_.resize(count), z_.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        const std::byte* at = records + i * stride;
        x_[i] = load_le<std::int32_t>(at) * file.record_scale[0] + file.record_offset[0];
        y_[i] = load_le<std::int32_t>(at + 4) * file.record_scale[1] + file.record_offset[1];
        z_[i] = load_le<std::int32_t>(at + 8) * file.record_scale[2] + file.record_offset[2];
    }
    const std::size_t done = file.transform->apply(x_.data(), y_.data(), z_.data(), count);
    if (done < count)
        throw_input_error(file.path,
                          "point record " +
                              std::to_string((decoded_ ? decoded_read_ : current_->records_read()) - count + done) +
                              " cannot be transformed to " + survey_->crs_line +
                              ": it lies outside the area of its coordinate system");
    const std::array<const std::vector<double>*, 3> value{&x_, &y_, &z_};
    for (std::size_t i = 0; i < count; ++i)
        for (int a = 0; a < 3; ++a) {
            const double raw = std::round(((*value[a])[i] - h.offset[a]) / h.scale[a]);
            store_le<std::int32_t>(records + i * stride + 4 * a,
                                   static_cast<std::int32_t>(std::clamp(raw, int32_lowest, int32_highest)));
        }
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
            if (!current_ && !decoded_) open_next();
            const SurveyFile& file = survey_->files[next_ - 1];
            const std::size_t wanted =
                static_cast<std::size_t>(std::min<std::uint64_t>(capacity - total, current_left()));
            std::byte* out = dst.data() + total * length;
            std::size_t got = 0;
            if (file.point_format == header_->point_format && file.record_length == length) {
                got = read_current({out, wanted * length});
            } else { // into the survey's layout: X, Y, Z, then colour where the survey has it
                scratch_.resize(wanted * file.record_length);
                got = read_current(scratch_);
                const int file_rgb = rgb_offset(file.point_format);
                std::memset(out, 0, got * length);
                for (std::size_t i = 0; i < got; ++i) {
                    const std::byte* from = scratch_.data() + i * file.record_length;
                    std::byte* to = out + i * length;
                    std::memcpy(to, from, 12);
                    if (survey_rgb >= 0 && file_rgb >= 0) std::memcpy(to + survey_rgb, from + file_rgb, 6);
                }
            }
            convert_positions(out, got, length, file);
            total += seen_ ? seen_(next_ - 1, out, got) : got;
            records_read_ += got;
            if (got == 0 || current_left() == 0) finish_current();
        }
    } catch (const Error&) {
        failed_ = next_ - 1;
        throw;
    }
    return total;
}

} // namespace lasmesh
