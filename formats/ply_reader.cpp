#include "formats/ply_reader.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "formats/format_error.hpp"
#include "formats/mapped_file.hpp"
#include "formats/ply_header.hpp"
#include "formats/point_values.hpp"
#include "formats/text_scan_parser.hpp"

namespace tlsmon {

namespace {

constexpr std::size_t no_offset = std::numeric_limits<std::size_t>::max();

// The vertex properties a Scan uses: indices into the element's properties, -1 when absent.
struct VertexFields {
    int x, y, z, intensity = -1, red = -1, green = -1, blue = -1;

    explicit VertexFields(const PlyElement& e)
        : x(e.find({"x"})), y(e.find({"y"})), z(e.find({"z"})) {
        intensity = e.find({"intensity", "Intensity", "scalar_Intensity", "scalar_intensity"});
        red = e.find({"red"}), green = e.find({"green"}), blue = e.find({"blue"});
        if (red < 0 || green < 0 || blue < 0) red = green = blue = -1;  // all three or none
    }
};

// The camera element PCL writes (pcl::PLYWriter): the sensor origin, the rows of its
// rotation, and the organised cloud's width and height.
struct Camera {
    double view[3] = {0, 0, 0};
    double axes[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    std::optional<std::uint64_t> viewport_x, viewport_y;
};

constexpr const char* camera_axis_names[9] = {"x_axisx", "x_axisy", "x_axisz", "y_axisx", "y_axisy",
                                              "y_axisz", "z_axisx", "z_axisy", "z_axisz"};

void set_camera_value(Camera& c, std::string_view name, double v) {
    if (name == "view_px") c.view[0] = v;
    if (name == "view_py") c.view[1] = v;
    if (name == "view_pz") c.view[2] = v;
    for (int k = 0; k < 9; ++k) {
        if (name == camera_axis_names[k]) c.axes[k] = v;
    }
    const auto side = [&]() -> std::optional<std::uint64_t> {
        if (!(v >= 0.0 && v <= 4294967295.0)) return std::nullopt;
        return static_cast<std::uint64_t>(v);
    };
    if (name == "viewportx") c.viewport_x = side();
    if (name == "viewporty") c.viewport_y = side();
}

class PlyParser {
  public:
    PlyParser(std::string_view bytes, const std::filesystem::path& path)
        : bytes_(bytes),
          path_(path),
          header_(parse_ply_header(bytes, path)),
          swap_((header_.encoding == PlyEncoding::binary_big_endian) ==
                (std::endian::native == std::endian::little)),
          text_(bytes.substr(header_.data_offset), path, header_.header_lines),
          pos_(header_.data_offset) {}

    Scan parse() {
        const PlyElement* vertex = nullptr;
        const PlyElement* camera = nullptr;
        for (const auto& e : header_.elements) {
            if (e.name == "vertex" && !vertex) vertex = &e;
            if (e.name == "camera" && !camera && e.count > 0) camera = &e;
        }
        if (!vertex) throw_format_error(path_, "has no vertex element");
        const VertexFields fields(*vertex);
        if (fields.x < 0 || fields.y < 0 || fields.z < 0) {
            throw_format_error(path_, "has no x, y and z vertex properties");
        }
        // Vertex indices are kept only while a camera may still declare an organised cloud.
        keep_index_ = camera && camera->find({"viewportx"}) >= 0 &&
                      camera->find({"viewporty"}) >= 0 &&
                      vertex->count <= std::numeric_limits<std::uint32_t>::max();

        Scan scan;
        scan.source = path_.string();
        Camera cam;
        bool vertex_read = false, camera_read = camera == nullptr;
        for (const auto& e : header_.elements) {
            if (vertex_read && camera_read) break;  // what follows is not used
            if (&e == vertex) {
                read_vertices(e, fields, scan);
                vertex_read = true;
            } else if (&e == camera) {
                cam = read_camera(e);
                camera_read = true;
            } else {
                skip_element(e);
            }
        }
        if (camera) apply_camera(cam, vertex->count, scan);
        return scan;
    }

  private:
    bool ascii() const { return header_.encoding == PlyEncoding::ascii; }

    [[noreturn]] void truncated(const PlyElement& e, std::uint64_t index) const {
        throw_at_byte(path_, pos_,
                      "file ends inside " + e.name + " " + std::to_string(index) + " of the " +
                          std::to_string(e.count) + " the header declares on line " +
                          std::to_string(e.header_line));
    }

    // Binary: one record of `e` from pos_; offsets[k] is where scalar property k's value is.
    void walk_record(const PlyElement& e, std::uint64_t index, std::size_t* offsets) {
        for (std::size_t k = 0; k < e.properties.size(); ++k) {
            const PlyProperty& p = e.properties[k];
            const std::size_t left = bytes_.size() - pos_;
            if (!p.is_list) {
                if (left < value_size(p.type)) truncated(e, index);
                if (offsets) offsets[k] = pos_;
                pos_ += value_size(p.type);
                continue;
            }
            if (left < value_size(p.count_type)) truncated(e, index);
            const double n = load_value(bytes_.data() + pos_, p.count_type, swap_);
            if (n < 0) throw_at_byte(path_, pos_, "negative list length in " + e.name);
            pos_ += value_size(p.count_type);
            if (n > static_cast<double>((left - value_size(p.count_type)) / value_size(p.type))) {
                truncated(e, index);
            }
            pos_ += static_cast<std::size_t>(n) * value_size(p.type);
            if (offsets) offsets[k] = no_offset;
        }
    }

    // ASCII: one record of `e` on the next line; tokens[k] is scalar property k's value.
    void split_record(const PlyElement& e, std::uint64_t index, std::string_view* tokens,
                      std::vector<std::string_view>& scratch) {
        std::string_view line;
        if (!text_.next_line(line)) {
            throw_at_line(path_, text_.line_number() + 1,
                          "file ends after " + std::to_string(index) + " of the " +
                              std::to_string(e.count) + " " + e.name +
                              " lines the header declares");
        }
        if (!e.has_lists()) {
            const std::size_t n = split_tokens(line, tokens, e.properties.size());
            if (n != e.properties.size()) {
                text_.fail(std::to_string(n) + " values, the header declares " +
                           std::to_string(e.properties.size()) + " per " + e.name);
            }
            return;
        }
        const std::size_t n = split_tokens(line, nullptr, 0);
        scratch.resize(n);
        split_tokens(line, scratch.data(), n);
        std::size_t t = 0;
        for (std::size_t k = 0; k < e.properties.size(); ++k) {
            if (t >= n) text_.fail("fewer values than the " + e.name + " properties declare");
            if (!e.properties[k].is_list) {
                tokens[k] = scratch[t++];
                continue;
            }
            const double count = parse_value(scratch[t++], text_);
            if (!(count >= 0.0) || count != std::floor(count) || count > static_cast<double>(n)) {
                text_.fail("list length '" + quote_token(scratch[t - 1]) + "' is not a count");
            }
            t += static_cast<std::size_t>(count);
        }
        if (t != n) {
            text_.fail(std::to_string(n) + " values, the " + e.name + " properties declare " +
                       std::to_string(t));
        }
    }

    void skip_element(const PlyElement& e) {
        if (e.properties.empty()) return;  // takes no bytes, whatever its count
        if (ascii()) {
            std::string_view line;
            for (std::uint64_t i = 0; i < e.count; ++i) {
                if (!text_.next_line(line)) {
                    throw_at_line(path_, text_.line_number() + 1,
                                  "file ends after " + std::to_string(i) + " of the " +
                                      std::to_string(e.count) + " " + e.name + " lines");
                }
            }
        } else if (!e.has_lists()) {
            const std::size_t stride = e.min_record_bytes();
            if (e.count > (bytes_.size() - pos_) / stride)
                truncated(e, (bytes_.size() - pos_) / stride);
            pos_ += e.count * stride;
        } else {
            for (std::uint64_t i = 0; i < e.count; ++i) walk_record(e, i, nullptr);
        }
    }

    // Binary: every record must be there before anything is reserved for them. ASCII: the
    // line loop finds a short file; the reservation is only capped by what the bytes can hold
    // (each value takes a character and a separator or line break).
    std::size_t checked_count(const PlyElement& e) const {
        const std::size_t left = bytes_.size() - pos_;
        if (ascii())
            return std::min<std::uint64_t>(e.count, (left + 1) / (2 * e.properties.size()));
        const std::size_t least = e.min_record_bytes();
        if (e.count > left / least) {
            throw_at_line(path_, e.header_line,
                          "element " + e.name + " declares " + std::to_string(e.count) +
                              " records of at least " + std::to_string(least) +
                              " bytes, but only " + std::to_string(left) + " bytes follow");
        }
        return static_cast<std::size_t>(e.count);
    }

    void read_vertices(const PlyElement& e, const VertexFields& f, Scan& scan) {
        const std::size_t room = checked_count(e);
        scan.xyz.reserve(room);
        if (f.intensity >= 0) scan.intensity.reserve(room);
        if (f.red >= 0) scan.rgb.reserve(room);
        if (keep_index_) index_.reserve(room);
        const std::uint64_t count = e.count;
        const auto& props = e.properties;
        const ValueType tx = props[f.x].type, ty = props[f.y].type, tz = props[f.z].type;
        const ValueType ti = f.intensity >= 0 ? props[f.intensity].type : ValueType::float32;
        IntensityScale scale(ti);

        const auto add = [&](std::size_t i, double x, double y, double z, auto&& intensity,
                             auto&& colour) {
            if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return;  // no return
            scan.xyz.emplace_back(x, y, z);
            if (f.intensity >= 0) {
                const double v = intensity();
                if (!std::isfinite(v)) fail_vertex(i, "intensity is " + std::to_string(v));
                scale.add(scan, static_cast<float>(v));
            }
            if (f.red >= 0) scan.rgb.push_back(colour());
            if (keep_index_) index_.push_back(static_cast<std::uint32_t>(i));
        };

        if (ascii()) {
            std::vector<std::string_view> tokens(props.size()), scratch;
            for (std::uint64_t i = 0; i < count; ++i) {
                split_record(e, i, tokens.data(), scratch);
                const auto value = [&](int k) { return parse_value(tokens[k], text_); };
                add(
                    i, value(f.x), value(f.y), value(f.z), [&] { return value(f.intensity); },
                    [&] {
                        return Rgb8{colour_channel(value(f.red), props[f.red].type),
                                    colour_channel(value(f.green), props[f.green].type),
                                    colour_channel(value(f.blue), props[f.blue].type)};
                    });
            }
        } else {
            std::vector<std::size_t> offsets(props.size());
            const bool lists = e.has_lists();
            const std::size_t stride = e.min_record_bytes();
            if (!lists) {
                for (std::size_t k = 0, at = 0; k < props.size(); ++k) {
                    offsets[k] = at;
                    at += value_size(props[k].type);
                }
            }
            const char* data = bytes_.data();
            for (std::size_t i = 0; i < count; ++i) {
                std::size_t base = 0;  // offsets are relative to `base`
                if (lists) {
                    vertex_at_ = pos_;
                    walk_record(e, i, offsets.data());
                } else {
                    base = pos_;  // checked_count made sure every record is there
                    vertex_at_ = pos_;
                    pos_ += stride;
                }
                const auto value = [&](int k, ValueType t) {
                    return load_value(data + base + offsets[k], t, swap_);
                };
                add(
                    i, value(f.x, tx), value(f.y, ty), value(f.z, tz),
                    [&] { return value(f.intensity, ti); },
                    [&] {
                        return Rgb8{
                            colour_channel(value(f.red, props[f.red].type), props[f.red].type),
                            colour_channel(value(f.green, props[f.green].type),
                                           props[f.green].type),
                            colour_channel(value(f.blue, props[f.blue].type), props[f.blue].type)};
                    });
            }
        }
        scale.normalise(scan);
    }

    [[noreturn]] void fail_vertex(std::size_t i, const std::string& what) const {
        if (ascii()) text_.fail("vertex " + std::to_string(i) + ": " + what);
        throw_at_byte(path_, vertex_at_, "vertex " + std::to_string(i) + ": " + what);
    }

    Camera read_camera(const PlyElement& e) {
        Camera cam;
        const auto& props = e.properties;
        if (ascii()) {
            std::vector<std::string_view> tokens(props.size()), scratch;
            split_record(e, 0, tokens.data(), scratch);
            for (std::size_t k = 0; k < props.size(); ++k) {
                if (!props[k].is_list)
                    set_camera_value(cam, props[k].name, parse_value(tokens[k], text_));
            }
        } else {
            std::vector<std::size_t> offsets(props.size());
            walk_record(e, 0, offsets.data());
            for (std::size_t k = 0; k < props.size(); ++k) {
                if (props[k].is_list) continue;
                set_camera_value(cam, props[k].name,
                                 load_value(bytes_.data() + offsets[k], props[k].type, swap_));
            }
        }
        PlyElement rest = e;  // further cameras are not used
        rest.count = e.count - 1;
        skip_element(rest);
        return cam;
    }

    void apply_camera(const Camera& cam, std::uint64_t vertices, Scan& scan) {
        const Eigen::Vector3d origin(cam.view[0], cam.view[1], cam.view[2]);
        Eigen::Matrix3d r;  // PCL reads x_axis* into the first row, and so on
        for (int k = 0; k < 9; ++k) r(k / 3, k % 3) = cam.axes[k];
        if (!origin.allFinite() || !r.allFinite() ||
            (r * r.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-3 ||
            r.determinant() < 0) {
            throw_format_error(path_,
                               "camera element: x_axis, y_axis, z_axis are not the rows of a "
                               "rotation, or the view point is not finite");
        }
        scan.pose = Eigen::Translation3d(origin) * Eigen::Quaterniond(r).normalized();

        if (keep_index_ && cam.viewport_x && cam.viewport_y && *cam.viewport_y > 1 &&
            *cam.viewport_x * *cam.viewport_y == vertices) {
            ScanGrid grid;
            grid.rows = static_cast<std::uint32_t>(*cam.viewport_y);
            grid.columns = static_cast<std::uint32_t>(*cam.viewport_x);
            grid.row.reserve(index_.size());
            grid.column.reserve(index_.size());
            for (std::uint32_t i : index_) {
                grid.row.push_back(i / grid.columns);
                grid.column.push_back(i % grid.columns);
            }
            scan.grid = std::move(grid);
        }
    }

    std::string_view bytes_;
    const std::filesystem::path& path_;
    PlyHeader header_;
    bool swap_;
    TextCursor text_;  // ascii: the data lines
    std::size_t pos_;  // binary: the next byte
    std::size_t vertex_at_ = 0;
    bool keep_index_ = false;
    std::vector<std::uint32_t> index_;  // vertex index of every point, for the grid
};

}  // namespace

std::vector<Scan> parse_ply(std::string_view bytes, const std::filesystem::path& path) {
    std::vector<Scan> scans;
    scans.push_back(PlyParser(bytes, path).parse());
    return scans;
}

std::vector<Scan> read_ply(const std::filesystem::path& path) {
    const MappedFile file(path);
    return parse_ply(file.text(), path);
}

}  // namespace tlsmon
