#include "formats/e57_xml.hpp"

#include <bit>
#include <charconv>
#include <cmath>
#include <limits>
#include <pugixml.hpp>

namespace tlsmon {

unsigned E57Field::bits() const {
    switch (type) {
        case E57FieldType::float_single:
            return 32;
        case E57FieldType::float_double:
            return 64;
        default:
            break;
    }
    const std::uint64_t range =
        static_cast<std::uint64_t>(maximum) - static_cast<std::uint64_t>(minimum);
    return range == 0 ? 0u : static_cast<unsigned>(64 - std::countl_zero(range));
}

double E57Field::declared_minimum() const {
    if (type == E57FieldType::float_single || type == E57FieldType::float_double)
        return float_minimum;
    return type == E57FieldType::scaled_integer ? static_cast<double>(minimum) * scale + offset
                                                : static_cast<double>(minimum);
}

double E57Field::declared_maximum() const {
    if (type == E57FieldType::float_single || type == E57FieldType::float_double)
        return float_maximum;
    return type == E57FieldType::scaled_integer ? static_cast<double>(maximum) * scale + offset
                                                : static_cast<double>(maximum);
}

namespace {

class XmlReader {
  public:
    XmlReader(const E57Pages& pages) : pages_(pages) {}

    std::uint64_t byte_of(const pugi::xml_node& n) const {
        const std::ptrdiff_t k = n.offset_debug();
        return pages_.xml_byte(k < 0 ? 0 : static_cast<std::uint64_t>(k));
    }

    [[noreturn]] void fail(const pugi::xml_node& n, const std::string& what) const {
        pages_.fail(byte_of(n), what);
    }

    static std::string_view trimmed(const char* s) {
        std::string_view v(s);
        while (!v.empty() && std::isspace(static_cast<unsigned char>(v.front())))
            v.remove_prefix(1);
        while (!v.empty() && std::isspace(static_cast<unsigned char>(v.back()))) v.remove_suffix(1);
        return v;
    }

    template <typename T>
    T number(const pugi::xml_node& n, const char* text, T fallback, const char* what) const {
        const std::string_view v = trimmed(text);
        if (v.empty()) return fallback;  // E2807 §9: an empty element holds the default 0
        T out{};
        const char* first = v.data();
        if (!v.empty() && v.front() == '+') ++first;
        const auto [end, ec] = std::from_chars(first, v.data() + v.size(), out);
        if (ec != std::errc() || end != v.data() + v.size())
            fail(n, std::string("element <") + n.name() + "> has a bad " + what + " '" +
                        std::string(v) + "'");
        return out;
    }

    // The numeric value of an Integer, ScaledInteger or Float element (E2807 §9.4-§9.6).
    double value(const pugi::xml_node& n) const {
        const std::string_view type = n.attribute("type").value();
        if (type == "Integer")
            return static_cast<double>(number<std::int64_t>(n, n.text().get(), 0, "integer"));
        if (type == "ScaledInteger") {
            const auto raw = number<std::int64_t>(n, n.text().get(), 0, "integer");
            const double scale = number<double>(n, n.attribute("scale").value(), 1.0, "scale");
            const double offset = number<double>(n, n.attribute("offset").value(), 0.0, "offset");
            return static_cast<double>(raw) * scale + offset;
        }
        if (type == "Float") return number<double>(n, n.text().get(), 0.0, "float");
        fail(n, std::string("element <") + n.name() + "> is not numeric (type '" +
                    std::string(type) + "')");
    }

    std::optional<double> child_value(const pugi::xml_node& parent, const char* name) const {
        const pugi::xml_node c = parent.child(name);
        if (!c) return std::nullopt;
        return value(c);
    }

    double child_value_or(const pugi::xml_node& parent, const char* name, double fallback) const {
        return child_value(parent, name).value_or(fallback);
    }

    E57Field field(const pugi::xml_node& n, const std::string& name) const {
        E57Field f;
        f.name = name;
        f.xml_byte = byte_of(n);
        const std::string_view type = n.attribute("type").value();
        if (type == "Integer" || type == "ScaledInteger") {
            f.type = type == "Integer" ? E57FieldType::integer : E57FieldType::scaled_integer;
            f.minimum = number<std::int64_t>(n, n.attribute("minimum").value(),
                                             std::numeric_limits<std::int64_t>::min(), "minimum");
            f.maximum = number<std::int64_t>(n, n.attribute("maximum").value(),
                                             std::numeric_limits<std::int64_t>::max(), "maximum");
            if (f.maximum < f.minimum)
                fail(n, "prototype field " + name + " has maximum < minimum");
            if (f.type == E57FieldType::scaled_integer) {
                f.scale = number<double>(n, n.attribute("scale").value(), 1.0, "scale");
                f.offset = number<double>(n, n.attribute("offset").value(), 0.0, "offset");
                if (!std::isfinite(f.scale) || f.scale == 0.0 || !std::isfinite(f.offset))
                    fail(n, "prototype field " + name + " has a bad scale or offset");
            }
        } else if (type == "Float") {
            const std::string_view precision = n.attribute("precision").value();
            const bool single = precision == "single";
            if (!single && !precision.empty() && precision != "double")
                fail(n,
                     "prototype field " + name + " has precision '" + std::string(precision) + "'");
            f.type = single ? E57FieldType::float_single : E57FieldType::float_double;
            const double big =
                single ? std::numeric_limits<float>::max() : std::numeric_limits<double>::max();
            f.float_minimum = number<double>(n, n.attribute("minimum").value(), -big, "minimum");
            f.float_maximum = number<double>(n, n.attribute("maximum").value(), big, "maximum");
        } else {
            fail(n, "prototype field " + name + " has type '" + std::string(type) +
                        "', which a compressed vector cannot hold here");
        }
        return f;
    }

    // Depth-first terminals of the prototype: one bytestream each, in document order.
    void flatten(const pugi::xml_node& n, const std::string& prefix, std::vector<E57Field>& out,
                 int depth) const {
        if (depth > 16) fail(n, "prototype nested too deeply");
        for (const pugi::xml_node c : n.children()) {
            if (c.type() != pugi::node_element) continue;
            const std::string name = prefix.empty() ? c.name() : prefix + "/" + c.name();
            const std::string_view type = c.attribute("type").value();
            if (type == "Structure" || type == "Vector")
                flatten(c, name, out, depth + 1);
            else
                out.push_back(field(c, name));
        }
    }

    E57CompressedVector points(const pugi::xml_node& n) const {
        if (std::string_view(n.attribute("type").value()) != "CompressedVector")
            fail(n, "<points> is not a CompressedVector");
        E57CompressedVector cv;
        cv.xml_byte = byte_of(n);
        cv.file_offset =
            number<std::uint64_t>(n, n.attribute("fileOffset").value(), 0, "fileOffset");
        cv.record_count =
            number<std::uint64_t>(n, n.attribute("recordCount").value(), 0, "recordCount");
        const pugi::xml_node proto = n.child("prototype");
        if (!proto) fail(n, "bad prototype: compressed vector <points> has no <prototype>");
        flatten(proto, "", cv.fields, 0);
        if (cv.fields.empty()) fail(proto, "bad prototype: <prototype> has no fields");
        const pugi::xml_node codecs = n.child("codecs");
        for (const pugi::xml_node c : codecs.children())
            if (c.type() == pugi::node_element)
                fail(c, "codec other than the default bitPackCodec is not supported");
        return cv;
    }

    Eigen::Affine3d pose(const pugi::xml_node& n) const {
        Eigen::Affine3d pose = Eigen::Affine3d::Identity();
        if (!n) return pose;
        // E2807 §10.4 RigidBodyTransform: a missing rotation or translation is the identity.
        if (const pugi::xml_node r = n.child("rotation")) {
            Eigen::Quaterniond q(child_value_or(r, "w", 0), child_value_or(r, "x", 0),
                                 child_value_or(r, "y", 0), child_value_or(r, "z", 0));
            const double norm = q.norm();
            if (!std::isfinite(norm) || std::abs(norm - 1.0) > 1e-3)
                fail(r,
                     "pose rotation is not a unit quaternion (norm " + std::to_string(norm) + ")");
            pose.linear() = q.normalized().toRotationMatrix();
        }
        if (const pugi::xml_node t = n.child("translation")) {
            const Eigen::Vector3d v(child_value_or(t, "x", 0), child_value_or(t, "y", 0),
                                    child_value_or(t, "z", 0));
            if (!v.allFinite()) fail(t, "pose translation is not finite");
            pose.translation() = v;
        }
        return pose;
    }

    std::optional<E57Range> range(const pugi::xml_node& n, const char* min_name,
                                  const char* max_name) const {
        if (!n) return std::nullopt;
        const auto lo = child_value(n, min_name);
        const auto hi = child_value(n, max_name);
        if (!lo && !hi) return std::nullopt;
        return E57Range{lo.value_or(0.0), hi.value_or(0.0)};
    }

    E57ScanInfo scan(const pugi::xml_node& n) const {
        E57ScanInfo s;
        s.xml_byte = byte_of(n);
        s.name = n.child("name").text().get();
        s.pose = pose(n.child("pose"));
        s.intensity_limits =
            range(n.child("intensityLimits"), "intensityMinimum", "intensityMaximum");
        const pugi::xml_node c = n.child("colorLimits");
        s.color_limits[0] = range(c, "colorRedMinimum", "colorRedMaximum");
        s.color_limits[1] = range(c, "colorGreenMinimum", "colorGreenMaximum");
        s.color_limits[2] = range(c, "colorBlueMinimum", "colorBlueMaximum");
        if (const pugi::xml_node b = n.child("indexBounds")) {
            E57IndexBounds ib;
            const auto get = [&](const char* name) {
                const pugi::xml_node e = b.child(name);
                return e ? number<std::int64_t>(e, e.text().get(), 0, "integer") : 0;
            };
            ib.row_minimum = get("rowMinimum");
            ib.row_maximum = get("rowMaximum");
            ib.column_minimum = get("columnMinimum");
            ib.column_maximum = get("columnMaximum");
            s.index_bounds = ib;
        }
        if (const pugi::xml_node a = n.child("acquisitionStart")) {
            const double t = child_value_or(a, "dateTimeValue", 0.0);
            // Writers leave the element empty (= 0, the GPS epoch itself) when they do not
            // know the time: treat 0 as "not given".
            if (std::isfinite(t) && t > 0.0) s.acquisition_start_gps = t;
        }
        const pugi::xml_node p = n.child("points");
        if (!p) fail(n, "data3D scan has no <points>");
        s.points = points(p);
        return s;
    }

  private:
    const E57Pages& pages_;
};

}  // namespace

std::vector<E57ScanInfo> parse_e57_xml(const E57Pages& pages, std::string_view xml) {
    pugi::xml_document doc;
    const pugi::xml_parse_result parsed =
        doc.load_buffer(xml.data(), xml.size(), pugi::parse_default, pugi::encoding_utf8);
    if (!parsed)
        pages.fail(
            pages.xml_byte(static_cast<std::uint64_t>(std::max<std::ptrdiff_t>(parsed.offset, 0))),
            std::string("XML section: ") + parsed.description());
    const XmlReader reader(pages);
    const pugi::xml_node root = doc.child("e57Root");
    if (!root) pages.fail(pages.header().xml_physical_offset, "XML section has no <e57Root>");
    std::vector<E57ScanInfo> scans;
    for (const pugi::xml_node c : root.child("data3D").children()) {
        if (c.type() != pugi::node_element) continue;
        scans.push_back(reader.scan(c));
    }
    return scans;
}

}  // namespace tlsmon
