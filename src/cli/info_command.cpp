// SPDX-License-Identifier: Apache-2.0
// `lasmesh info`: text for people, one JSON object with --json; with several inputs, each file's
// facts and then the survey's (the union the mesh would cover).
#include "info_command.hpp"

#include "tileset_info.hpp"

#include "io/json.hpp"
#include "lasmesh/error.hpp"
#include "lasmesh/las_reader.hpp"
#include "read/crs.hpp"
#include "read/input_stream.hpp"
#include "read/las_scan.hpp"
#include "read/survey.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <optional>
#include <sstream>

namespace lasmesh::cli {

namespace {

std::string join(const Vec3& v) {
    return format_double(v[0]) + " " + format_double(v[1]) + " " + format_double(v[2]);
}

// Header strings are arbitrary bytes: escape sequences among them would drive the terminal.
std::string escaped(const std::string& raw) {
    static const char* hex = "0123456789abcdef";
    std::string text;
    for (unsigned char c : raw) {
        if (c >= 0x20 && c < 0x7F)
            text += static_cast<char>(c);
        else
            text += std::string("\\x") + hex[c >> 4] + hex[c & 15];
    }
    return text;
}

// Coordinates to the decimals the file's scale can hold (scale 0.001: 3), for people; --json
// keeps every digit.
std::string join_scaled(const Vec3& v, const Vec3& scale) {
    std::string text;
    for (int a = 0; a < 3; ++a) {
        const double step = scale[a] > 0 && std::isfinite(scale[a]) ? scale[a] : 1;
        const int decimals = std::clamp(static_cast<int>(std::ceil(-std::log10(step) - 1e-9)), 0, 12);
        std::ostringstream number;
        if (std::isfinite(v[a]) && std::abs(v[a]) < 1e15)
            number << std::fixed << std::setprecision(decimals) << v[a];
        else
            number << format_double(v[a]);
        text += (a ? " " : "") + number.str();
    }
    return text;
}

std::string join(const Rgb16& v) {
    return std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]);
}

// COPC files are LAZ whose first VLR is the "copc" info record (COPC 1.0 specification).
bool is_copc(const LasHeader& h) {
    for (const Vlr& vlr : h.vlrs)
        if (vlr.user_id == "copc" && vlr.record_id == 1) return true;
    return false;
}

std::string records_text(const LasHeader& h) {
    if (!h.compressed) return "LAS (uncompressed)";
    return is_copc(h) ? "LAZ (LASzip-compressed), COPC (cloud-optimised: chunks in an octree)"
                      : "LAZ (LASzip-compressed)";
}

std::string crs_line(const LasHeader& h) {
    const std::optional<CrsInfo> crs = read_crs(h);
    return crs ? crs_summary(*crs) : "none declared (coordinates in the file's own units)";
}

Json header_json(const LasHeader& h, const std::optional<ScanResult>& scan) {
    Json json;
    json["version"] = version_string(h);
    json["records"] = !h.compressed ? "las" : is_copc(h) ? "copc" : "laz";
    json["point_format"] = h.point_format;
    json["point_record_length"] = h.point_record_length;
    json["point_count"] = h.point_count;
    json["scale"] = h.scale;
    json["offset"] = h.offset;
    json["bounds"] = {{"min", h.min}, {"max", h.max}};
    json["has_color"] = has_color(h);
    if (const std::optional<CrsInfo> crs = read_crs(h))
        json["crs"] = {{"source", crs->source},
                       {"name", crs->name},
                       {"code", crs->code},
                       {"kind", crs->kind},
                       {"unit", crs->unit},
                       {"unit_metres", crs->unit_metres},
                       {"vertical", crs->vertical},
                       {"vertical_unit", crs->vertical_unit},
                       {"vertical_unit_metres", crs->vertical_unit_metres},
                       {"wkt", crs->wkt},
                       {"problem", crs->problem}};
    else
        json["crs"] = nullptr;
    json["vlrs"] = Json::array();
    for (const Vlr& vlr : h.vlrs)
        json["vlrs"].push_back({{"user_id", latin1_to_utf8(vlr.user_id)},
                                {"record_id", vlr.record_id},
                                {"length", vlr.length},
                                {"description", latin1_to_utf8(vlr.description)}});
    json["evlr_count"] = h.evlr_count;
    json["crs_evlrs"] = Json::array();
    for (const Vlr& vlr : h.crs_evlrs)
        json["crs_evlrs"].push_back({{"record_id", vlr.record_id},
                                     {"length", vlr.data.size()},
                                     {"description", latin1_to_utf8(vlr.description)}});
    if (scan)
        json["scanned"] = {{"point_count", scan->point_count},
                           {"bounds", {{"min", scan->min}, {"max", scan->max}}},
                           {"color_min", scan->color_min},
                           {"color_max", scan->color_max}};
    return json;
}

// What several inputs are as one survey: how many points, the frame and layout their records are
// read in, the union of their bounds, the CRS; or why they cannot be meshed together.
struct SurveyFacts {
    std::optional<Survey> survey;
    std::string problem;
    bool same_frame = true, same_layout = true;
};

SurveyFacts survey_facts(const std::vector<std::string>& inputs) {
    SurveyFacts facts;
    try {
        facts.survey = read_survey(inputs, SurveyOptions{false, false, {}});
    } catch (const Error& e) {
        facts.problem = e.what();
        return facts;
    }
    for (const SurveyFile& file : facts.survey->files) {
        if (file.point_count == 0) continue;
        facts.same_frame =
            facts.same_frame && file.scale == facts.survey->header.scale && file.offset == facts.survey->header.offset;
        facts.same_layout = facts.same_layout && file.point_format == facts.survey->header.point_format &&
                            file.record_length == facts.survey->header.point_record_length;
    }
    return facts;
}

Json survey_json(const SurveyFacts& facts) {
    if (!facts.survey) return {{"problem", facts.problem}};
    const LasHeader& h = facts.survey->header;
    return {{"files", facts.survey->files.size()},
            {"point_count", h.point_count},
            {"point_format", h.point_format},
            {"point_record_length", h.point_record_length},
            {"same_layout", facts.same_layout},
            {"scale", h.scale},
            {"offset", h.offset},
            {"same_frame", facts.same_frame},
            {"bounds", {{"min", h.min}, {"max", h.max}}},
            {"crs", facts.survey->crs_line},
            {"notes", facts.survey->notes}};
}

void write_survey_text(const SurveyFacts& facts, std::ostream& out) {
    if (!facts.survey) {
        out << "survey               cannot be meshed as one: " << facts.problem << '\n';
        return;
    }
    const LasHeader& h = facts.survey->header;
    out << "survey               " << facts.survey->files.size() << " files, " << h.point_count << " points\n"
        << "read as              point format " << int(h.point_format) << " (" << h.point_record_length
        << "-byte records" << (facts.same_layout ? ", as every file" : ": X, Y, Z and colour of files in others")
        << ")\nscale                " << join(h.scale) << "\noffset               " << join(h.offset)
        << (facts.same_frame ? "  (every file's)" : "  (the files differ: records brought into this frame)")
        << "\nbounds min           " << join_scaled(h.min, h.scale) << "\nbounds max           "
        << join_scaled(h.max, h.scale) << "\ncrs                  "
        << (facts.survey->crs ? facts.survey->crs_line : "none declared (coordinates in the files' own units)") << '\n';
    for (const std::string& note : facts.survey->notes) out << note << '\n';
}

void write_text(const LasReader& reader, const std::optional<ScanResult>& scan, std::ostream& out) {
    const LasHeader& h = reader.header();
    const InputStream& in = reader.stream();
    out << "input                " << in.name();
    if (in.compression() != Compression::none) out << " (" << compression_name(in.compression()) << ")";
    out << "\nversion              " << version_string(h) << "\nrecords              " << records_text(h)
        << "\npoint format         " << int(h.point_format) << " (" << h.point_record_length << "-byte records, "
        << core_record_size(h.point_format) << " core + " << h.point_record_length - core_record_size(h.point_format)
        << " extra)"
        << "\npoint count          " << h.point_count << "\nhas color            " << (has_color(h) ? "yes" : "no")
        << "\nscale                " << join(h.scale) << "\noffset               " << join(h.offset)
        << "\nbounds min           " << join_scaled(h.min, h.scale) << "\nbounds max           "
        << join_scaled(h.max, h.scale) << "\ncrs                  " << crs_line(h) << "\nsystem identifier    "
        << escaped(h.system_identifier) << "\ngenerating software  " << escaped(h.generating_software)
        << "\nVLRs                 " << h.vlrs.size() << '\n';
    for (const Vlr& vlr : h.vlrs)
        out << "  " << escaped(vlr.user_id) << " / " << vlr.record_id << "  " << vlr.length << " bytes  "
            << escaped(vlr.description) << '\n';
    if (h.evlr_count > 0) {
        out << "EVLRs                " << h.evlr_count << " (from byte " << h.evlr_start << ")\n";
        for (const Vlr& vlr : h.crs_evlrs)
            out << "  LASF_Projection / " << vlr.record_id << "  " << vlr.data.size() << " bytes  "
                << escaped(vlr.description) << '\n';
    }
    if (scan) {
        out << "scanned point count  " << scan->point_count << "\nscanned bounds min   "
            << join_scaled(scan->min, h.scale) << "\nscanned bounds max   " << join_scaled(scan->max, h.scale) << '\n';
        if (scan->has_color)
            out << "scanned color min    " << join(scan->color_min) << "\nscanned color max    "
                << join(scan->color_max) << '\n';
    }
}

} // namespace

void run_info(const InfoOptions& options, std::ostream& out, std::ostream& log) {
    for (const std::string& input : options.inputs)
        if (is_tileset_path(input)) {
            if (options.inputs.size() > 1 || options.scan)
                throw Error(ErrorKind::usage, "a tileset (" + input + ") is shown alone, without --scan", "inputs");
            return write_tileset_info(input, options.json, out);
        }
    Json files = Json::array();
    for (const std::string& input : options.inputs) {
        LasReader reader(input);
        std::optional<ScanResult> scan;
        if (options.scan) scan = scan_points(reader, options.chunk_points);
        if (const std::string warning = trailing_warning(reader); !warning.empty())
            log << "lasmesh: " << warning << '\n';
        if (options.json)
            files.push_back(header_json(reader.header(), scan));
        else
            write_text(reader, scan, out << (&input == &options.inputs.front() ? "" : "\n"));
    }
    if (options.inputs.size() == 1) {
        if (options.json) out << json_line(files.front()) << '\n';
        return;
    }
    const SurveyFacts facts = survey_facts(options.inputs);
    if (options.json) {
        out << json_line(Json{{"files", files}, {"survey", survey_json(facts)}}) << '\n';
        return;
    }
    write_survey_text(facts, out << '\n');
}

} // namespace lasmesh::cli
