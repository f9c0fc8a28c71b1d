#include "formats/geojson_writer.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

#include "core/csv.hpp"
#include "core/error.hpp"

namespace tlsmon {

namespace {

constexpr std::size_t kBlock = 1 << 20;

// A JSON string (RFC 8259 §7): quotes, backslash and control characters escaped.
void append_string(std::string& out, std::string_view text) {
    out += '"';
    for (const char ch : text) {
        switch (ch) {
            case '"':
                out += "\\\"";
                break;
            case '\\':
                out += "\\\\";
                break;
            case '\n':
                out += "\\n";
                break;
            case '\t':
                out += "\\t";
                break;
            default:
                if (static_cast<unsigned char>(ch) < 0x20) {
                    char hex[8];
                    std::snprintf(hex, sizeof hex, "\\u%04x", static_cast<unsigned>(ch));
                    out += hex;
                } else {
                    out += ch;
                }
        }
    }
    out += '"';
}

void append_number(std::string& out, double v) {
    const std::string text = csv_number(v);  // shortest exact decimals; "" for NaN, ±inf
    out += text.empty() ? "null" : text;
}

void append_value(std::string& out, const GeoJsonValue& v) {
    if (std::holds_alternative<std::monostate>(v)) {
        out += "null";
    } else if (const auto* s = std::get_if<std::string>(&v)) {
        append_string(out, *s);
    } else if (const auto* d = std::get_if<double>(&v)) {
        append_number(out, *d);
    } else if (const auto* i = std::get_if<std::int64_t>(&v)) {
        out += std::to_string(*i);
    } else {
        out += std::get<bool>(v) ? "true" : "false";
    }
}

}  // namespace

std::string geojson_crs_name(const std::string& urn, const std::string& wkt) {
    if (!urn.empty()) return urn;
    return wkt.empty() ? kLocalFrameCrs : wkt;
}

GeoJsonWriter::GeoJsonWriter(std::filesystem::path path, const std::string& crs_name)
    : path_(std::move(path)), part_(path_.string() + ".part") {
    out_.open(part_, std::ios::binary | std::ios::trunc);
    if (!out_) throw Error("cannot write " + part_.string() + ": " + std::strerror(errno));
    buf_ = "{\"type\":\"FeatureCollection\",";
    if (!crs_name.empty()) {
        buf_ += "\"crs\":{\"type\":\"name\",\"properties\":{\"name\":";
        append_string(buf_, crs_name);
        buf_ += "}},";
    }
    buf_ += "\"features\":[\n";
}

GeoJsonWriter::~GeoJsonWriter() {
    if (finished_) return;
    out_.close();
    std::error_code ec;
    std::filesystem::remove(part_, ec);
}

void GeoJsonWriter::feature(std::string_view geometry, const GeoJsonProperties& properties) {
    if (features_++ > 0) buf_ += ",\n";
    buf_ += "{\"type\":\"Feature\",\"geometry\":";
    buf_ += geometry;
    buf_ += ",\"properties\":{";
    for (std::size_t i = 0; i < properties.size(); ++i) {
        if (i > 0) buf_ += ',';
        append_string(buf_, properties[i].first);
        buf_ += ':';
        append_value(buf_, properties[i].second);
    }
    buf_ += "}}";
    if (buf_.size() >= kBlock) flush();
}

void GeoJsonWriter::flush() {
    out_ << buf_;
    buf_.clear();
    if (!out_) throw Error("cannot write " + part_.string() + ": " + std::strerror(errno));
}

void GeoJsonWriter::finish() {
    buf_ += "\n]}\n";
    flush();
    out_.close();
    if (!out_) throw Error("cannot write " + part_.string() + ": " + std::strerror(errno));
    std::error_code ec;
    std::filesystem::rename(part_, path_, ec);
    if (ec) {
        throw Error("cannot rename " + part_.string() + " to " + path_.string() + ": " +
                    ec.message());
    }
    finished_ = true;
}

std::string geojson_point(const Eigen::Vector3d& p) {
    std::string out = "{\"type\":\"Point\",\"coordinates\":[";
    for (int k = 0; k < 3; ++k) {
        if (k > 0) out += ',';
        append_number(out, p[k]);
    }
    return out + "]}";
}

std::string geojson_polygon(const std::vector<std::pair<double, double>>& ring) {
    std::string out = "{\"type\":\"Polygon\",\"coordinates\":[[";
    auto closed = ring;
    if (!closed.empty() && closed.front() != closed.back()) closed.push_back(closed.front());
    // Counter-clockwise, as RFC 7946 §3.1.6 asks of an exterior ring (shoelace sign).
    double twice_area = 0;
    for (std::size_t i = 0; i + 1 < closed.size(); ++i) {
        twice_area +=
            closed[i].first * closed[i + 1].second - closed[i + 1].first * closed[i].second;
    }
    if (twice_area < 0) std::reverse(closed.begin(), closed.end());
    for (std::size_t i = 0; i < closed.size(); ++i) {
        if (i > 0) out += ',';
        out += '[';
        append_number(out, closed[i].first);
        out += ',';
        append_number(out, closed[i].second);
        out += ']';
    }
    return out + "]]}";
}

void write_geojson_points(const std::filesystem::path& path, const LasPoints& points,
                          const std::string& crs_name) {
    GeoJsonWriter w(path, crs_name);
    GeoJsonProperties properties;
    for (const auto& a : points.attributes) properties.emplace_back(a.name, 0.0);
    for (std::size_t i = 0; i < points.xyz.size(); ++i) {
        for (std::size_t k = 0; k < points.attributes.size(); ++k) {
            const auto& a = points.attributes[k];
            const double v = a.values[i];
            if (a.type == LasAttribute::Type::f32 || a.type == LasAttribute::Type::f64) {
                properties[k].second = v;
            } else {
                properties[k].second = static_cast<std::int64_t>(v);
            }
        }
        w.feature(geojson_point(points.xyz[i]), properties);
    }
    w.finish();
}

}  // namespace tlsmon
