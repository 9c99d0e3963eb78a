// SPDX-License-Identifier: Apache-2.0
// CrsTransform, crs_from_text and utm_crs_for, on PROJ's C API. UTM zones as the UTM grid defines
// them: 6 degrees wide from 180 W, with zone 32V widened to 3-12 E (56-64 N) and zones 31X-37X
// redrawn (72-84 N).
#include "read/crs_transform.hpp"

#include "lasmesh/error.hpp"
#include "read/proj_handles.hpp"

#include <proj_experimental.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace lasmesh {

using proj::Context;
using proj::Object;

namespace {

// A CRS object from what CrsInfo kept of it (PROJ's WKT2).
Object crs_object(PJ_CONTEXT* ctx, const CrsInfo& crs) {
    return Object(crs.wkt.empty() ? nullptr : proj_create(ctx, crs.wkt.c_str()));
}

int utm_zone(double longitude, double latitude) {
    int zone = static_cast<int>(std::floor((longitude + 180) / 6)) + 1;
    zone = std::clamp(zone, 1, 60);
    if (latitude >= 56 && latitude < 64 && longitude >= 3 && longitude < 12) return 32;
    if (latitude >= 72 && latitude < 84 && longitude >= 0 && longitude < 42)
        return longitude < 9 ? 31 : longitude < 21 ? 33 : longitude < 33 ? 35 : 37;
    return zone;
}

} // namespace

CrsInfo crs_from_text(const std::string& text) {
    const Context ctx = proj::quiet_context();
    const Object crs(proj_create(ctx.get(), text.c_str()));
    if (!crs || !proj_is_crs(crs.get()))
        throw Error(ErrorKind::usage,
                    "\"" + text.substr(0, 80) + "\" is not a coordinate system PROJ knows: give EPSG:CODE or a WKT",
                    "crs");
    return describe_crs(ctx.get(), crs.get(), "the CRS asked for");
}

CrsInfo utm_crs_for(const CrsInfo& geographic, double longitude, double latitude) {
    const Context ctx = proj::quiet_context();
    const Object source = crs_object(ctx.get(), geographic);
    Object horizontal, vertical;
    PJ* h = source.get();
    if (source && proj_get_type(source.get()) == PJ_TYPE_COMPOUND_CRS) {
        horizontal.reset(proj_crs_get_sub_crs(ctx.get(), source.get(), 0));
        vertical.reset(proj_crs_get_sub_crs(ctx.get(), source.get(), 1));
        h = horizontal.get();
    }
    const Object datum(h ? proj_crs_get_geodetic_crs(ctx.get(), h) : nullptr);
    const int zone = utm_zone(longitude, latitude);
    const bool north = latitude >= 0;
    const Object conversion(proj_create_conversion_utm(ctx.get(), zone, north ? 1 : 0));
    const Object axes(proj_create_cartesian_2D_cs(ctx.get(), PJ_CART2D_EASTING_NORTHING, "metre", 1.0));
    const std::string name = std::string(datum && proj_get_name(datum.get()) ? proj_get_name(datum.get()) : "") +
                             " / UTM zone " + std::to_string(zone) + (north ? "N" : "S");
    Object projected(datum && conversion && axes
                         ? proj_create_projected_crs(ctx.get(), name.c_str(), datum.get(), conversion.get(), axes.get())
                         : nullptr);
    if (!projected)
        throw Error(ErrorKind::input, "PROJ could not make the UTM zone " + std::to_string(zone) +
                                          " CRS on the datum of " + crs_summary(geographic));
    // The EPSG entry it equals (WGS 84 / UTM zone 31N is EPSG:32631), so that outputs can name it.
    int* confidence = nullptr;
    PJ_OBJ_LIST* matches = proj_identify(ctx.get(), projected.get(), "EPSG", nullptr, &confidence);
    if (matches && proj_list_get_count(matches) > 0 && confidence && confidence[0] >= 90)
        projected.reset(proj_list_get(ctx.get(), matches, 0));
    proj_int_list_destroy(confidence);
    proj_list_destroy(matches);
    if (vertical) {
        const std::string compound_name =
            std::string(proj_get_name(projected.get())) + " + " + proj_get_name(vertical.get());
        Object compound(proj_create_compound_crs(ctx.get(), compound_name.c_str(), projected.get(), vertical.get()));
        if (compound) return describe_crs(ctx.get(), compound.get(), geographic.source);
    }
    return describe_crs(ctx.get(), projected.get(), geographic.source);
}

struct CrsTransform::Impl {
    Context ctx = proj::quiet_context();
    Object operation;
    std::string file, from, to;
};

CrsTransform::CrsTransform(const CrsInfo& from, const CrsInfo& to, const std::string& file)
    : impl_(std::make_unique<Impl>()) {
    impl_->file = file, impl_->from = crs_summary(from), impl_->to = crs_summary(to);
    PJ_CONTEXT* ctx = impl_->ctx.get();
    const Object source = crs_object(ctx, from), target = crs_object(ctx, to);
    Object operation(
        source && target ? proj_create_crs_to_crs_from_pj(ctx, source.get(), target.get(), nullptr, nullptr) : nullptr);
    // x east (or longitude) first, whatever axis order the CRS's definition gives.
    if (operation) impl_->operation.reset(proj_normalize_for_visualization(ctx, operation.get()));
    if (!impl_->operation)
        throw_input_error(file, "PROJ has no transformation from its coordinate system " + impl_->from + " to " +
                                    impl_->to + " (nothing was written)");
}

CrsTransform::~CrsTransform() = default;

std::size_t CrsTransform::apply(double* x, double* y, double* z, std::size_t n) const {
    proj_trans_generic(impl_->operation.get(), PJ_FWD, x, sizeof(double), n, y, sizeof(double), n, z, sizeof(double), n,
                       nullptr, 0, 0);
    for (std::size_t i = 0; i < n; ++i)
        if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || !std::isfinite(z[i])) return i;
    return n;
}

Bounds CrsTransform::bounds(const Bounds& box) const {
    Bounds out;
    if (!proj_trans_bounds(impl_->ctx.get(), impl_->operation.get(), PJ_FWD, box.min[0], box.min[1], box.max[0],
                           box.max[1], &out.min[0], &out.min[1], &out.max[0], &out.max[1], 21))
        throw_input_error(impl_->file, "its header bounds lie outside the area where " + impl_->from +
                                           " can be transformed to " + impl_->to);
    // Heights can change with the horizontal position (a geoid, an ellipsoid): z over a lattice of
    // the box at its lowest and highest.
    constexpr int steps = 20;
    std::vector<double> x, y, z;
    for (const double height : {box.min[2], box.max[2]})
        for (int i = 0; i <= steps; ++i)
            for (int j = 0; j <= steps; ++j) {
                x.push_back(box.min[0] + (box.max[0] - box.min[0]) * i / steps);
                y.push_back(box.min[1] + (box.max[1] - box.min[1]) * j / steps);
                z.push_back(height);
            }
    if (apply(x.data(), y.data(), z.data(), x.size()) != x.size())
        throw_input_error(impl_->file, "its header bounds lie outside the area where " + impl_->from +
                                           " can be transformed to " + impl_->to);
    out.min[2] = *std::min_element(z.begin(), z.end());
    out.max[2] = *std::max_element(z.begin(), z.end());
    for (std::size_t i = 0; i < x.size(); ++i) { // corners and the lattice too, should PROJ's edges miss any
        out.min[0] = std::min(out.min[0], x[i]), out.max[0] = std::max(out.max[0], x[i]);
        out.min[1] = std::min(out.min[1], y[i]), out.max[1] = std::max(out.max[1], y[i]);
    }
    return out;
}

} // namespace lasmesh
