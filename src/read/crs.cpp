// SPDX-License-Identifier: Apache-2.0
// read_crs: the GeoTIFF keys decoded as the GeoTIFF 1.1 specification (OGC 19-008r4) lays them
// out, and the LAS 1.4 WKT VLR; PROJ builds the CRS, names it, finds its EPSG code and units.
#include "read/crs.hpp"

#include "byte_order.hpp"
#include "number_text.hpp"
#include "read/proj_handles.hpp"

#include <proj.h>
#include <proj_experimental.h> // proj_create_compound_crs: a horizontal and a vertical CRS from GeoTIFF keys

#include <map>
#include <memory>

namespace lasmesh {

using proj::Context;
using proj::Object;

namespace {

constexpr const char* projection_user_id = "LASF_Projection";
constexpr std::uint16_t wkt_record = 2112, key_directory_record = 34735, doubles_record = 34736, ascii_record = 34737;
// GeoTIFF keys lasmesh reads (GeoTIFF 1.1, annex B).
constexpr std::uint16_t model_type_key = 1024, citation_key = 1026, geographic_type_key = 2048,
                        projected_type_key = 3072, projected_citation_key = 3073, vertical_type_key = 4096;
constexpr std::uint16_t user_defined = 32767;

const Vlr* find_vlr(const LasHeader& header, std::uint16_t record) {
    for (const std::vector<Vlr>* list : {&header.vlrs, &header.crs_evlrs})
        for (const Vlr& vlr : *list)
            if (vlr.user_id == projection_user_id && vlr.record_id == record && !vlr.data.empty()) return &vlr;
    return nullptr;
}

// One key: its short value, or the text it points to in the ASCII record.
struct GeoKey {
    std::uint16_t value = 0;
    std::string text;
};

std::map<std::uint16_t, GeoKey> geo_keys(const LasHeader& header) {
    std::map<std::uint16_t, GeoKey> keys;
    const Vlr* directory = find_vlr(header, key_directory_record);
    if (!directory || directory->data.size() < 8) return keys;
    const Vlr* ascii = find_vlr(header, ascii_record);
    const std::byte* d = directory->data.data();
    const std::size_t count = load_le<std::uint16_t>(d + 6);
    for (std::size_t k = 0; k < count && 8 + 8 * (k + 1) <= directory->data.size(); ++k) {
        const std::byte* entry = d + 8 + 8 * k;
        const auto id = load_le<std::uint16_t>(entry), location = load_le<std::uint16_t>(entry + 2),
                   n = load_le<std::uint16_t>(entry + 4), value = load_le<std::uint16_t>(entry + 6);
        GeoKey key;
        if (location == 0) key.value = value;
        if (location == ascii_record && ascii && std::size_t{value} + n <= ascii->data.size()) {
            key.text.assign(reinterpret_cast<const char*>(ascii->data.data()) + value, n);
            while (!key.text.empty() && (key.text.back() == '|' || key.text.back() == '\0')) key.text.pop_back();
        }
        keys[id] = key;
    }
    return keys;
}

Object from_epsg(PJ_CONTEXT* ctx, int code) {
    return Object(proj_create_from_database(ctx, "EPSG", std::to_string(code).c_str(), PJ_CATEGORY_CRS, 0, nullptr));
}

// "EPSG:2992": the object's own identifier, else the EPSG entry PROJ finds equivalent to it.
std::string code_of(PJ_CONTEXT* ctx, const PJ* crs) {
    if (const char* auth = proj_get_id_auth_name(crs, 0))
        if (const char* code = proj_get_id_code(crs, 0)) return std::string(auth) + ":" + code;
    int* confidence = nullptr;
    PJ_OBJ_LIST* matches = proj_identify(ctx, crs, "EPSG", nullptr, &confidence);
    std::string found;
    if (matches && proj_list_get_count(matches) > 0 && confidence && confidence[0] >= 90) {
        const Object best(proj_list_get(ctx, matches, 0));
        if (const char* code = proj_get_id_code(best.get(), 0)) found = std::string("EPSG:") + code;
    }
    proj_int_list_destroy(confidence);
    proj_list_destroy(matches);
    return found;
}

// The unit of a CRS's first axis and its conversion factor (metres, or radians for angles).
std::pair<std::string, double> unit_of(PJ_CONTEXT* ctx, const PJ* crs) {
    const Object cs(proj_crs_get_coordinate_system(ctx, crs));
    const char* unit = nullptr;
    double factor = 0;
    if (!cs || !proj_cs_get_axis_info(ctx, cs.get(), 0, nullptr, nullptr, nullptr, &factor, &unit, nullptr, nullptr))
        return {"", 0};
    return {unit ? unit : "", factor};
}

} // namespace

CrsInfo describe_crs(PJ_CONTEXT* ctx, PJ* crs, const std::string& source) {
    CrsInfo info;
    info.source = source;
    Object unbound;
    if (proj_get_type(crs) == PJ_TYPE_BOUND_CRS) { // WKT1 with TOWGS84: the CRS it is bound from
        unbound.reset(proj_get_source_crs(ctx, crs));
        if (unbound) crs = unbound.get();
    }
    info.name = proj_get_name(crs) ? proj_get_name(crs) : "";
    info.code = code_of(ctx, crs);
    Object horizontal, vertical;
    PJ* h = crs;
    if (proj_get_type(crs) == PJ_TYPE_COMPOUND_CRS) {
        horizontal.reset(proj_crs_get_sub_crs(ctx, crs, 0));
        vertical.reset(proj_crs_get_sub_crs(ctx, crs, 1));
        if (horizontal) h = horizontal.get();
    }
    switch (proj_get_type(h)) {
    case PJ_TYPE_PROJECTED_CRS: info.kind = "projected"; break;
    case PJ_TYPE_GEOGRAPHIC_2D_CRS:
    case PJ_TYPE_GEOGRAPHIC_3D_CRS: info.kind = "geographic"; break;
    case PJ_TYPE_GEOCENTRIC_CRS: info.kind = "geocentric"; break;
    default: info.kind = "other";
    }
    const auto [unit, factor] = unit_of(ctx, h);
    info.unit = unit;
    info.unit_metres = info.geographic() ? 0 : factor;
    if (vertical) {
        info.vertical = proj_get_name(vertical.get()) ? proj_get_name(vertical.get()) : "";
        const auto [vertical_unit, vertical_factor] = unit_of(ctx, vertical.get());
        info.vertical_unit = vertical_unit;
        info.vertical_unit_metres = vertical_factor;
    }
    const char* one_line[] = {"MULTILINE=NO", nullptr};
    if (const char* wkt = proj_as_wkt(ctx, crs, PJ_WKT2_2019, one_line)) info.wkt = wkt;
    return info;
}

namespace {

CrsInfo from_wkt(PJ_CONTEXT* ctx, const Vlr& vlr) {
    std::string text(reinterpret_cast<const char*>(vlr.data.data()), vlr.data.size());
    while (!text.empty() && text.back() == '\0') text.pop_back();
    const char* options[] = {"STRICT=NO", nullptr};
    PROJ_STRING_LIST warnings = nullptr, errors = nullptr;
    const Object crs(proj_create_from_wkt(ctx, text.c_str(), options, &warnings, &errors));
    std::string problem = errors && errors[0] ? errors[0] : "not a CRS PROJ reads";
    proj_string_list_destroy(warnings);
    proj_string_list_destroy(errors);
    if (!crs) {
        CrsInfo info;
        info.source = "OGC WKT";
        info.problem =
            "its WKT (\"" + text.substr(0, 60) + (text.size() > 60 ? "...\"" : "\"") + ") is unreadable: " + problem;
        return info;
    }
    return describe_crs(ctx, crs.get(), "OGC WKT");
}

CrsInfo from_geo_keys(PJ_CONTEXT* ctx, const std::map<std::uint16_t, GeoKey>& keys) {
    const auto value = [&](std::uint16_t key) { return keys.count(key) ? keys.at(key).value : std::uint16_t{0}; };
    const auto text = [&](std::uint16_t key) { return keys.count(key) ? keys.at(key).text : std::string(); };
    const std::uint16_t projected = value(projected_type_key), geographic = value(geographic_type_key),
                        vertical = value(vertical_type_key), model = value(model_type_key);
    const auto usable = [](std::uint16_t code) { return code >= 1024 && code < user_defined; };
    CrsInfo failed;
    failed.source = "GeoTIFF keys";
    Object horizontal;
    if (usable(projected) && model != 2)
        horizontal = from_epsg(ctx, projected);
    else if (usable(geographic))
        horizontal = from_epsg(ctx, geographic);
    if (!horizontal) {
        const std::string citation =
            !text(projected_citation_key).empty() ? text(projected_citation_key) : text(citation_key);
        failed.problem = (projected == user_defined || geographic == user_defined)
                             ? "a user-defined GeoTIFF CRS PROJ cannot build from its keys"
                             : "GeoTIFF keys without an EPSG code PROJ knows (projected " + std::to_string(projected) +
                                   ", geographic " + std::to_string(geographic) + ")";
        if (!citation.empty()) failed.problem += ", citation \"" + citation + "\"";
        return failed;
    }
    if (usable(vertical))
        if (const Object v = from_epsg(ctx, vertical)) {
            const std::string name = std::string(proj_get_name(horizontal.get())) + " + " + proj_get_name(v.get());
            const Object compound(proj_create_compound_crs(ctx, name.c_str(), horizontal.get(), v.get()));
            if (compound) return describe_crs(ctx, compound.get(), "GeoTIFF keys");
        }
    return describe_crs(ctx, horizontal.get(), "GeoTIFF keys");
}

} // namespace

std::optional<CrsInfo> read_crs(const LasHeader& header) {
    const Vlr* wkt = find_vlr(header, wkt_record);
    const std::map<std::uint16_t, GeoKey> keys = geo_keys(header);
    if (!wkt && keys.empty()) return std::nullopt;
    const Context ctx = proj::quiet_context();
    const bool wkt_bit = (header.global_encoding & 0x10) != 0;
    if (wkt && (wkt_bit || keys.empty())) return from_wkt(ctx.get(), *wkt);
    return from_geo_keys(ctx.get(), keys);
}

std::string crs_summary(const CrsInfo& crs) {
    if (!crs.identified()) return "from its " + crs.source + ", not identified: " + crs.problem;
    std::string text = crs.name + (crs.code.empty() ? "" : " (" + crs.code + ")") + ", " + crs.kind;
    if (!crs.unit.empty())
        text += ", in " + crs.unit +
                (crs.unit_metres > 0 && crs.unit_metres != 1 ? " (" + significant(crs.unit_metres, 7) + " m)" : "");
    if (!crs.vertical.empty())
        text += "; vertical " + crs.vertical + (crs.vertical_unit.empty() ? "" : ", in " + crs.vertical_unit);
    return text;
}

std::string crs_for_outputs(const CrsInfo& crs) {
    return crs.code.empty() ? crs.wkt : crs.code;
}

} // namespace lasmesh
