#include "formats/e57_writer.hpp"

#include <algorithm>
#include <bit>
#include <boost/crc.hpp>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include "core/utc_time.hpp"
#include "formats/e57_pages.hpp"
#include "formats/e57_reader.hpp"
#include "formats/format_error.hpp"

namespace tlsmon {

namespace {

using Crc32c = boost::crc_optimal<32, 0x1EDC6F41, 0xFFFFFFFF, 0xFFFFFFFF, true, true>;

// Logical bytes written at physical positions (checksum slots skipped); the checksums are
// filled in by finish(), once every byte of every page is final.
class PageFile {
  public:
    explicit PageFile(const std::filesystem::path& path) : path_(path) {
        out_.open(path, std::ios::binary | std::ios::in | std::ios::out | std::ios::trunc);
        if (!out_) throw_format_error(path, "cannot create");
    }

    std::uint64_t end() const { return end_; }

    void write_at(std::uint64_t logical, const void* data, std::uint64_t n) {
        const auto* p = static_cast<const char*>(data);
        while (n > 0) {
            const std::uint64_t chunk = std::min(n, e57_page_payload - logical % e57_page_payload);
            out_.seekp(static_cast<std::streamoff>(E57Pages::to_physical(logical)));
            out_.write(p, static_cast<std::streamsize>(chunk));
            p += chunk;
            logical += chunk;
            n -= chunk;
        }
        end_ = std::max(end_, logical);
    }
    std::uint64_t append(const void* data, std::uint64_t n) {
        const std::uint64_t at = end_;
        write_at(at, data, n);
        return at;
    }

    // Pads the last page and writes every page's CRC-32C, big-endian (E2807 §8).
    std::uint64_t finish() {
        const std::uint64_t pages = (end_ + e57_page_payload - 1) / e57_page_payload;
        std::vector<char> page(e57_page_size);
        for (std::uint64_t k = 0; k < pages; ++k) {
            std::fill(page.begin(), page.end(), 0);
            out_.seekg(static_cast<std::streamoff>(k * e57_page_size));
            out_.read(page.data(), static_cast<std::streamsize>(e57_page_payload));
            out_.clear();  // the last page may be short before padding
            Crc32c crc;
            crc.process_bytes(page.data(), e57_page_payload);
            const std::uint32_t c = crc.checksum();
            for (int i = 0; i < 4; ++i)
                page[e57_page_payload + i] = static_cast<char>(c >> (24 - 8 * i));
            out_.seekp(static_cast<std::streamoff>(k * e57_page_size));
            out_.write(page.data(), static_cast<std::streamsize>(e57_page_size));
        }
        out_.flush();
        if (!out_) throw_format_error(path_, "write failed");
        return pages * e57_page_size;
    }

  private:
    std::filesystem::path path_;
    std::fstream out_;
    std::uint64_t end_ = 0;
};

void put_le(std::vector<std::uint8_t>& b, std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

// One prototype field being written: its XML and its bit-packed stream for one packet.
struct FieldWriter {
    std::string xml;
    bool is_float = false;  // Float double, else Integer/ScaledInteger raw counts
    std::int64_t minimum = 0;
    unsigned bits = 0;
    std::vector<std::uint8_t> bytes;
    std::uint64_t acc = 0;
    unsigned acc_bits = 0;

    void put_float(double v) { put_le(bytes, std::bit_cast<std::uint64_t>(v), 8); }
    void put_int(std::int64_t raw) {
        const std::uint64_t u =
            static_cast<std::uint64_t>(raw) - static_cast<std::uint64_t>(minimum);
        for (unsigned done = 0; done < bits;) {  // least significant bits first
            const unsigned take = std::min(bits - done, 8 - acc_bits);
            acc |= ((u >> done) & ((1u << take) - 1)) << acc_bits;
            acc_bits += take;
            done += take;
            if (acc_bits == 8) {
                bytes.push_back(static_cast<std::uint8_t>(acc));
                acc = 0;
                acc_bits = 0;
            }
        }
    }
    void flush_bits() {  // only at the end of the stream
        if (acc_bits > 0) bytes.push_back(static_cast<std::uint8_t>(acc));
        acc = 0;
        acc_bits = 0;
    }
};

unsigned bits_for(std::int64_t lo, std::int64_t hi) {
    const auto range = static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo);
    return range == 0 ? 0u : static_cast<unsigned>(64 - std::countl_zero(range));
}

std::string num(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

FieldWriter integer_field(const std::string& name, std::int64_t lo, std::int64_t hi,
                          double scale = 0.0) {
    FieldWriter f;
    f.minimum = lo;
    f.bits = bits_for(lo, hi);
    f.xml = "<" + name + (scale > 0 ? " type=\"ScaledInteger\"" : " type=\"Integer\"") +
            " minimum=\"" + std::to_string(lo) + "\" maximum=\"" + std::to_string(hi) + "\"" +
            (scale > 0 ? " scale=\"" + num(scale) + "\"" : "") + "/>";
    return f;
}
FieldWriter float_field(const std::string& name) {
    FieldWriter f;
    f.is_float = true;
    f.bits = 64;
    f.xml = "<" + name + " type=\"Float\"/>";
    return f;
}

constexpr std::size_t records_per_packet = 1024;  // a multiple of 8: whole bytes per packet

// Writes the points of one scan as a compressed-vector section; returns its XML.
std::string write_scan(PageFile& file, const Scan& scan, const E57WriteOptions& o, std::size_t k) {
    const Eigen::Affine3d to_scanner = scan.pose.inverse();
    std::vector<Eigen::Vector3d> local(scan.size());
    for (std::size_t i = 0; i < scan.size(); ++i) local[i] = to_scanner * scan.xyz[i];

    std::vector<FieldWriter> fields;
    std::int64_t lo = 0, hi = 0;
    if (o.spherical) {
        for (const char* n : {"sphericalRange", "sphericalAzimuth", "sphericalElevation"})
            fields.push_back(float_field(n));
    } else if (o.coordinate_scale > 0) {
        for (const auto& p : local)
            for (int a = 0; a < 3; ++a) {
                const auto r = std::llround(p[a] / o.coordinate_scale);
                lo = std::min<std::int64_t>(lo, r);
                hi = std::max<std::int64_t>(hi, r);
            }
        for (const char* n : {"cartesianX", "cartesianY", "cartesianZ"})
            fields.push_back(integer_field(n, lo, hi, o.coordinate_scale));
    } else {
        for (const char* n : {"cartesianX", "cartesianY", "cartesianZ"})
            fields.push_back(float_field(n));
    }
    const bool intensity = !scan.intensity.empty();
    const bool colour = !scan.rgb.empty();
    const bool grid = scan.grid.has_value();
    constexpr std::int64_t intensity_counts = 4095;  // 12 bits: not a whole number of bytes
    if (intensity) fields.push_back(integer_field("intensity", 0, intensity_counts));
    if (colour)
        for (const char* n : {"colorRed", "colorGreen", "colorBlue"})
            fields.push_back(integer_field(n, 0, 255));
    if (grid) {
        fields.push_back(
            integer_field("rowIndex", 0, std::max<std::int64_t>(scan.grid->rows, 1) - 1));
        fields.push_back(
            integer_field("columnIndex", 0, std::max<std::int64_t>(scan.grid->columns, 1) - 1));
    }
    if (o.invalid_every > 0)
        fields.push_back(
            integer_field(o.spherical ? "sphericalInvalidState" : "cartesianInvalidState", 0, 2));

    const auto put_record = [&](std::size_t i, bool invalid) {
        std::size_t f = 0;
        const Eigen::Vector3d& p = local[i];
        if (o.spherical) {
            const double r = p.norm();
            fields[f++].put_float(r);
            fields[f++].put_float(std::atan2(p.y(), p.x()));
            fields[f++].put_float(r > 0 ? std::asin(p.z() / r) : 0.0);
        } else if (o.coordinate_scale > 0) {
            for (int a = 0; a < 3; ++a)
                fields[f++].put_int(std::llround(p[a] / o.coordinate_scale));
        } else {
            for (int a = 0; a < 3; ++a) fields[f++].put_float(p[a]);
        }
        if (intensity)
            fields[f++].put_int(
                std::llround(std::clamp(scan.intensity[i], 0.0f, 1.0f) * intensity_counts));
        if (colour)
            for (int c = 0; c < 3; ++c) fields[f++].put_int(scan.rgb[i][c]);
        if (grid) {
            fields[f++].put_int(scan.grid->row[i]);
            fields[f++].put_int(scan.grid->column[i]);
        }
        if (o.invalid_every > 0) fields[f++].put_int(invalid ? 2 : 0);
    };

    // Section header placeholder, then data packets; the header is written last.
    const std::uint64_t section = file.end();
    const std::vector<std::uint8_t> zeros(32, 0);
    file.append(zeros.data(), zeros.size());
    std::uint64_t records = 0;
    std::size_t in_packet = 0;
    const auto flush_packet = [&](bool last) {
        if (last)
            for (auto& f : fields) f.flush_bits();
        std::vector<std::uint8_t> packet;
        packet.push_back(1);  // data packet
        packet.push_back(0);
        put_le(packet, 0, 2);  // length - 1, below
        put_le(packet, fields.size(), 2);
        for (auto& f : fields) put_le(packet, f.bytes.size(), 2);
        for (auto& f : fields) {
            packet.insert(packet.end(), f.bytes.begin(), f.bytes.end());
            f.bytes.clear();
        }
        while (packet.size() % 4 != 0) packet.push_back(0);
        if (packet.size() > 65536) throw Error("E57 writer: packet too large");
        const std::uint64_t len = packet.size() - 1;
        packet[2] = static_cast<std::uint8_t>(len);
        packet[3] = static_cast<std::uint8_t>(len >> 8);
        file.append(packet.data(), packet.size());
        in_packet = 0;
    };
    for (std::size_t i = 0; i < scan.size(); ++i) {
        put_record(i, false);
        ++records;
        if (++in_packet == records_per_packet) flush_packet(false);
        if (o.invalid_every > 0 && (i + 1) % o.invalid_every == 0) {
            put_record(i, true);
            ++records;
            if (++in_packet == records_per_packet) flush_packet(false);
        }
    }
    if (in_packet > 0 || records == 0) flush_packet(true);

    std::vector<std::uint8_t> header;
    header.push_back(1);  // compressed-vector section
    header.resize(8, 0);
    put_le(header, file.end() - section, 8);
    put_le(header, E57Pages::to_physical(section + 32), 8);
    put_le(header, 0, 8);
    file.write_at(section, header.data(), header.size());

    const Eigen::Quaterniond q(scan.pose.linear());
    const Eigen::Vector3d t = scan.pose.translation();
    std::string xml = "<vectorChild type=\"Structure\">\n<name type=\"String\"><![CDATA[" +
                      (scan.name.empty() ? "scan " + std::to_string(k) : scan.name) +
                      "]]></name>\n";
    xml += "<pose type=\"Structure\"><rotation type=\"Structure\"><w type=\"Float\">" + num(q.w()) +
           "</w><x type=\"Float\">" + num(q.x()) + "</x><y type=\"Float\">" + num(q.y()) +
           "</y><z type=\"Float\">" + num(q.z()) +
           "</z></rotation><translation type=\"Structure\">"
           "<x type=\"Float\">" +
           num(t.x()) + "</x><y type=\"Float\">" + num(t.y()) + "</y><z type=\"Float\">" +
           num(t.z()) + "</z></translation></pose>\n";
    if (intensity)
        xml +=
            "<intensityLimits type=\"Structure\"><intensityMinimum "
            "type=\"Integer\">0</intensityMinimum>"
            "<intensityMaximum type=\"Integer\">" +
            std::to_string(intensity_counts) + "</intensityMaximum></intensityLimits>\n";
    if (grid)
        xml +=
            "<indexBounds type=\"Structure\"><rowMinimum "
            "type=\"Integer\">0</rowMinimum><rowMaximum "
            "type=\"Integer\">" +
            std::to_string(std::max<std::int64_t>(scan.grid->rows, 1) - 1) +
            "</rowMaximum><columnMinimum type=\"Integer\">0</columnMinimum><columnMaximum "
            "type=\"Integer\">" +
            std::to_string(std::max<std::int64_t>(scan.grid->columns, 1) - 1) +
            "</columnMaximum></indexBounds>\n";
    if (scan.acquired_utc) {
        const double gps = utc_to_gps(*scan.acquired_utc);
        xml += "<acquisitionStart type=\"Structure\"><dateTimeValue type=\"Float\">" + num(gps) +
               "</dateTimeValue></acquisitionStart>\n";
    }
    xml += "<points type=\"CompressedVector\" fileOffset=\"" +
           std::to_string(E57Pages::to_physical(section)) + "\" recordCount=\"" +
           std::to_string(records) + "\">\n<prototype type=\"Structure\">\n";
    for (const auto& f : fields) xml += f.xml + "\n";
    xml +=
        "</prototype>\n<codecs type=\"Vector\" "
        "allowHeterogeneousChildren=\"1\"/>\n</points>\n</vectorChild>\n";
    return xml;
}

}  // namespace

void write_e57(const std::filesystem::path& path, const std::vector<Scan>& scans,
               const E57WriteOptions& options) {
    PageFile file(path);
    const std::vector<std::uint8_t> header_space(48, 0);
    file.append(header_space.data(), header_space.size());
    std::string data3d;
    for (std::size_t k = 0; k < scans.size(); ++k) data3d += write_scan(file, scans[k], options, k);
    const std::string xml =
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<e57Root type=\"Structure\" "
        "xmlns=\"http://www.astm.org/COMMIT/E57/2010-e57-v1.0\">\n"
        "<formatName type=\"String\"><![CDATA[ASTM E57 3D Imaging Data File]]></formatName>\n"
        "<versionMajor type=\"Integer\">1</versionMajor>\n<versionMinor type=\"Integer\"/>\n"
        "<data3D type=\"Vector\" allowHeterogeneousChildren=\"1\">\n" +
        data3d +
        "</data3D>\n<images2D type=\"Vector\" allowHeterogeneousChildren=\"1\"/>\n</e57Root>\n";
    const std::uint64_t xml_at = file.append(xml.data(), xml.size());
    const std::uint64_t pages = (file.end() + e57_page_payload - 1) / e57_page_payload;

    // E2807 §8.2 file header.
    std::vector<std::uint8_t> h;
    for (const char c : std::string("ASTM-E57")) h.push_back(static_cast<std::uint8_t>(c));
    put_le(h, 1, 4);
    put_le(h, 0, 4);
    put_le(h, pages * e57_page_size, 8);
    put_le(h, E57Pages::to_physical(xml_at), 8);
    put_le(h, xml.size(), 8);
    put_le(h, e57_page_size, 8);
    file.write_at(0, h.data(), h.size());
    file.finish();
}

}  // namespace tlsmon
