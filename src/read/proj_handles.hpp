// SPDX-License-Identifier: Apache-2.0
// PROJ's contexts and objects as owning handles (released however the code that made them ends),
// and a CRS object described as lasmesh reports it.
#pragma once

#include "read/crs.hpp"

#include <proj.h>

#include <memory>
#include <string>

namespace lasmesh::proj {

struct ContextDeleter {
    void operator()(PJ_CONTEXT* c) const { proj_context_destroy(c); }
};
struct ObjectDeleter {
    void operator()(PJ* p) const { proj_destroy(p); }
};
using Context = std::unique_ptr<PJ_CONTEXT, ContextDeleter>;
using Object = std::unique_ptr<PJ, ObjectDeleter>;

// A context that logs nothing: every failure is reported by lasmesh, in its words.
inline Context quiet_context() {
    Context context(proj_context_create());
    proj_log_level(context.get(), PJ_LOG_NONE);
    return context;
}

} // namespace lasmesh::proj

namespace lasmesh {

// PROJ's CRS object described: name, EPSG code, kind, units, WKT (`source` says where it came
// from: "OGC WKT", "GeoTIFF keys", "the CRS asked for").
CrsInfo describe_crs(PJ_CONTEXT* context, PJ* crs, const std::string& source);

} // namespace lasmesh
