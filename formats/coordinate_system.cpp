#include "formats/coordinate_system.hpp"

#include <proj.h>

#include <memory>

#include "core/error.hpp"

namespace tlsmon {

CoordinateSystem coordinate_system(const std::string& crs) {
    const std::unique_ptr<PJ_CONTEXT, decltype(&proj_context_destroy)> ctx(proj_context_create(),
                                                                           &proj_context_destroy);
    if (!ctx) throw Error("cannot start PROJ");
    // PROJ's reason, which its error code alone does not tell, goes into the Error below.
    std::string reason;
    proj_log_level(ctx.get(), PJ_LOG_ERROR);
    proj_log_func(ctx.get(), &reason, [](void* to, int, const char* message) {
        *static_cast<std::string*>(to) = message;
    });
    const std::unique_ptr<PJ, decltype(&proj_destroy)> object(proj_create(ctx.get(), crs.c_str()),
                                                              &proj_destroy);
    if (!object) {
        if (reason.empty())
            reason = proj_context_errno_string(ctx.get(), proj_context_errno(ctx.get()));
        throw Error("'" + crs + "' is not a coordinate reference system PROJ knows: " + reason);
    }
    if (!proj_is_crs(object.get())) {
        throw Error("'" + crs + "' is a coordinate operation, not a coordinate reference system");
    }
    const char* const one_line[] = {"MULTILINE=NO", nullptr};
    const char* wkt = proj_as_wkt(ctx.get(), object.get(), PJ_WKT1_GDAL, one_line);
    if (wkt == nullptr) wkt = proj_as_wkt(ctx.get(), object.get(), PJ_WKT2_2019, one_line);
    if (wkt == nullptr) throw Error("PROJ cannot write '" + crs + "' as WKT");
    CoordinateSystem out{wkt, ""};
    // The OGC URN form (OGC 07-092r1), as GeoJSON's 2008 "crs" member and GDAL read it.
    const char* authority = proj_get_id_auth_name(object.get(), 0);
    const char* code = proj_get_id_code(object.get(), 0);
    if (authority != nullptr && code != nullptr) {
        out.urn = std::string("urn:ogc:def:crs:") + authority + "::" + code;
    }
    return out;
}

}  // namespace tlsmon
