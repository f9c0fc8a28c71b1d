#pragma once
// GeoJSON (RFC 7946) feature collections, written as they come: a map of a hundred thousand
// points is never held as a JSON tree. Coordinates are in the site's project frame, not
// WGS 84 (RFC 7946 §4 allows another system by prior arrangement); the file names it in the
// 2008 specification's "crs" member, which GDAL/OGR and QGIS read (without one they would
// take the coordinates for longitude and latitude).
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "formats/las_points.hpp"

namespace tlsmon {

// A property's value: null, text, a number (NaN and infinities are written as null), an
// integer or a flag.
using GeoJsonValue = std::variant<std::monostate, std::string, double, std::int64_t, bool>;
using GeoJsonProperties = std::vector<std::pair<std::string, GeoJsonValue>>;

// The "crs" name of a local frame: GDAL reads a WKT there as well as a URN.
inline constexpr const char* kLocalFrameCrs =
    "LOCAL_CS[\"tlsmon project frame\",UNIT[\"metre\",1]]";

// What names `system` in a GeoJSON file: its OGC URN ("urn:ogc:def:crs:EPSG::25832") when it
// has an authority code, else its WKT; a local frame when it is empty.
std::string geojson_crs_name(const std::string& urn, const std::string& wkt);

class GeoJsonWriter {
  public:
    // Writes to `path` + ".part" until finish() renames it; `crs_name` (geojson_crs_name)
    // into the "crs" member, none when "".
    GeoJsonWriter(std::filesystem::path path, const std::string& crs_name);
    GeoJsonWriter(const GeoJsonWriter&) = delete;
    GeoJsonWriter& operator=(const GeoJsonWriter&) = delete;
    ~GeoJsonWriter();  // an unfinished file's .part is removed

    // One feature: `geometry` a GeoJSON geometry object's text, or "null".
    void feature(std::string_view geometry, const GeoJsonProperties& properties);
    void finish();  // ends the collection; throws Error naming the file on a write failure

  private:
    void flush();

    std::filesystem::path path_, part_;
    std::ofstream out_;
    std::string buf_;
    std::size_t features_ = 0;
    bool finished_ = false;
};

// A Point geometry's text: [x, y, z] in the shortest decimals that read back exactly.
std::string geojson_point(const Eigen::Vector3d& p);
// A Polygon geometry's text from a closed or open ring of (x, y) vertices, turned
// counter-clockwise (RFC 7946 §3.1.6).
std::string geojson_polygon(const std::vector<std::pair<double, double>>& ring);

// Every point as a Point feature, its attributes as properties (NaN as null).
void write_geojson_points(const std::filesystem::path& path, const LasPoints& points,
                          const std::string& crs_name);

}  // namespace tlsmon
