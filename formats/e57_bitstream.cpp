#include "formats/e57_bitstream.hpp"

#include <algorithm>
#include <cstring>

namespace tlsmon {

namespace {

constexpr std::uint64_t section_header_size = 32;
constexpr std::uint8_t compressed_vector_section_id = 1;
constexpr std::uint8_t index_packet = 0, data_packet = 1, empty_packet = 2;
constexpr std::size_t batch_for_constant_fields = 65536;

std::uint64_t le64(const std::uint8_t* p) {
    std::uint64_t v;
    std::memcpy(&v, p, 8);  // E57 is little-endian, as is every target of this project
    return v;
}
std::uint16_t le16(const std::uint8_t* p) {
    return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}

// One bytestream: the bytes received so far that are not yet decoded, and its values.
class Bytestream {
  public:
    explicit Bytestream(const E57Field& f) : field_(f), bits_(f.bits()) {}

    bool constant() const { return bits_ == 0; }

    void append(const std::uint8_t* p, std::size_t n) {
        // Drop whole bytes already decoded, keep the bit offset into the first one.
        const std::size_t used = bit_ / 8;
        if (used > 0) {
            bytes_.erase(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(used));
            bit_ -= used * 8;
        }
        bytes_.insert(bytes_.end(), p, p + n);
    }

    // Decodes as many whole values as the received bytes hold, up to `limit` in total.
    void decode(std::uint64_t limit, std::vector<double>& out) {
        const std::uint64_t avail_bits = bytes_.size() * 8 - bit_;
        std::uint64_t n = bits_ == 0 ? 0 : avail_bits / bits_;
        n = std::min(n, limit - decoded_);
        if (n == 0) return;
        const std::size_t first = out.size();
        out.resize(first + n);
        double* dst = out.data() + first;
        const std::size_t size = bytes_.size();
        bytes_.resize(size + 16, 0);  // lets every load read 16 bytes without a bound check
        const std::uint8_t* b = bytes_.data();
        switch (field_.type) {
            case E57FieldType::float_single:
                for (std::uint64_t i = 0; i < n; ++i, bit_ += 32) {
                    float f;
                    std::memcpy(&f, b + bit_ / 8, 4);  // Float is byte aligned
                    dst[i] = f;
                }
                break;
            case E57FieldType::float_double:
                for (std::uint64_t i = 0; i < n; ++i, bit_ += 64)
                    std::memcpy(&dst[i], b + bit_ / 8, 8);
                break;
            default: {
                const unsigned w = bits_;
                const std::uint64_t mask =
                    w == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << w) - 1;
                const auto minimum = static_cast<std::uint64_t>(field_.minimum);
                const bool scaled = field_.type == E57FieldType::scaled_integer;
                for (std::uint64_t i = 0; i < n; ++i, bit_ += w) {
                    const std::uint8_t* p = b + bit_ / 8;
                    const unsigned shift = static_cast<unsigned>(bit_ % 8);
                    std::uint64_t raw = le64(p) >> shift;
                    if (shift + w > 64) raw |= std::uint64_t{p[8]} << (64 - shift);
                    const auto v = static_cast<std::int64_t>((raw & mask) + minimum);
                    dst[i] = scaled ? static_cast<double>(v) * field_.scale + field_.offset
                                    : static_cast<double>(v);
                }
            }
        }
        bytes_.resize(size);
        decoded_ += n;
    }

    double constant_value() const {
        return field_.type == E57FieldType::scaled_integer
                   ? static_cast<double>(field_.minimum) * field_.scale + field_.offset
                   : static_cast<double>(field_.minimum);
    }

    std::uint64_t decoded() const { return decoded_; }

  private:
    const E57Field& field_;
    unsigned bits_;
    std::vector<std::uint8_t> bytes_;
    std::uint64_t bit_ = 0;
    std::uint64_t decoded_ = 0;
};

struct Section {
    std::uint64_t begin = 0;  // logical offsets
    std::uint64_t end = 0;
    std::uint64_t data = 0;
};

// E2807 Table: CompressedVectorSectionHeader {uint8 sectionId = 1; uint8 reserved[7];
// uint64 sectionLogicalLength; uint64 dataPhysicalOffset; uint64 indexPhysicalOffset}.
Section read_section_header(E57Pages& pages, const E57CompressedVector& cv) {
    const std::uint64_t at = cv.file_offset;
    if (at < 48 || at >= pages.physical_size() || !E57Pages::is_payload(at)) {
        if (cv.record_count == 0)
            pages.fail(cv.xml_byte,
                       "invalid zero-record data: compressed vector with 0 records "
                       "has fileOffset " +
                           std::to_string(at) + ", which is not a binary section");
        pages.fail(cv.xml_byte, "compressed vector fileOffset " + std::to_string(at) +
                                    " is not a binary section of the file");
    }
    std::uint8_t h[section_header_size];
    Section s;
    s.begin = E57Pages::to_logical(at);
    pages.read(s.begin, section_header_size, h);
    const auto bad = [&](const std::string& what) {
        pages.fail(at, "bad compressed-vector section header: " + what);
    };
    if (h[0] != compressed_vector_section_id)
        bad("section id " + std::to_string(h[0]) + ", expected 1");
    const std::uint64_t length = le64(h + 8);
    const std::uint64_t data = le64(h + 16);
    const std::uint64_t index = le64(h + 24);
    if (length < section_header_size || length > pages.logical_size() - s.begin)
        bad("section length " + std::to_string(length) + " does not fit in the file");
    s.end = s.begin + length;
    const auto inside = [&](std::uint64_t physical) {
        return E57Pages::is_payload(physical) &&
               E57Pages::to_logical(physical) >= s.begin + section_header_size &&
               E57Pages::to_logical(physical) < s.end;
    };
    if (cv.record_count > 0 && !inside(data))
        bad("data offset " + std::to_string(data) + " is outside the section");
    if (index != 0 && !inside(index))
        bad("index offset " + std::to_string(index) + " is outside the section");
    s.data = E57Pages::to_logical(data);
    return s;
}

}  // namespace

void decode_e57_records(E57Pages& pages, const E57CompressedVector& cv,
                        const std::vector<std::size_t>& wanted, const E57RecordBatch& batch) {
    const Section section = read_section_header(pages, cv);
    const std::uint64_t total = cv.record_count;
    if (total == 0) return;

    // Declared sizes against the file before allocating: every stream needs
    // ceil(bits * records / 8) bytes inside the section.
    std::uint64_t record_bits = 0;
    for (const E57Field& f : cv.fields) record_bits += f.bits();
    const std::uint64_t section_bits = (section.end - section.begin) * 8;
    if (record_bits > 0 ? total > section_bits / record_bits : total > section_bits)
        pages.fail(cv.xml_byte, "recordCount " + std::to_string(total) +
                                    " does not fit in the compressed-vector section of " +
                                    std::to_string(section.end - section.begin) + " bytes");

    std::vector<Bytestream> streams;
    streams.reserve(wanted.size());
    for (const std::size_t k : wanted) streams.emplace_back(cv.fields.at(k));
    std::vector<std::vector<double>> columns(wanted.size());
    const bool all_constant = std::all_of(streams.begin(), streams.end(),
                                          [](const Bytestream& s) { return s.constant(); });

    std::uint64_t emitted = 0;
    // Hands over the records every wanted stream has decoded; constant (0-bit) fields are
    // filled in here instead of materialising recordCount copies up front.
    const auto emit = [&](std::uint64_t ready) {
        if (ready == 0) return;
        for (std::size_t k = 0; k < streams.size(); ++k)
            if (streams[k].constant()) columns[k].assign(ready, streams[k].constant_value());
        batch(columns, ready);
        for (std::size_t k = 0; k < streams.size(); ++k)
            if (!streams[k].constant())
                columns[k].erase(columns[k].begin(),
                                 columns[k].begin() + static_cast<std::ptrdiff_t>(ready));
        emitted += ready;
    };

    if (all_constant) {
        while (emitted < total)
            emit(std::min<std::uint64_t>(total - emitted, batch_for_constant_fields));
        return;
    }

    std::vector<std::uint8_t> packet(65536);
    std::uint64_t at = section.data;
    while (emitted < total) {
        const std::uint64_t physical = E57Pages::to_physical(at);
        if (at + 4 > section.end)
            pages.fail(physical, "compressed vector ends after " + std::to_string(emitted) +
                                     " of " + std::to_string(total) + " records");
        pages.read(at, 4, packet.data());
        const std::uint8_t type = packet[0];
        const std::uint64_t length = std::uint64_t{le16(packet.data() + 2)} + 1;
        if (at + length > section.end)
            pages.fail(physical, "packet of " + std::to_string(length) +
                                     " bytes runs past the end of its section");
        if (type == data_packet) {
            pages.read(at, length, packet.data());
            // DataPacketHeader {uint8 packetType; uint8 flags; uint16 lengthMinus1;
            // uint16 bytestreamCount} then uint16 bufferLength[bytestreamCount].
            if (length < 6) pages.fail(physical, "data packet shorter than its header");
            const std::size_t count = le16(packet.data() + 4);
            if (count != cv.fields.size())
                pages.fail(physical, "data packet has " + std::to_string(count) +
                                         " bytestreams, the prototype has " +
                                         std::to_string(cv.fields.size()) + " fields");
            std::size_t offset = 6 + 2 * count;
            if (offset > length) pages.fail(physical, "data packet header longer than the packet");
            std::vector<std::size_t> begin(count), size(count);
            for (std::size_t k = 0; k < count; ++k) {
                begin[k] = offset;
                size[k] = le16(packet.data() + 6 + 2 * k);
                offset += size[k];
            }
            if (offset > length) pages.fail(physical, "bytestream buffers overrun the data packet");
            std::uint64_t ready = total - emitted;
            for (std::size_t k = 0; k < streams.size(); ++k) {
                if (streams[k].constant()) continue;
                const std::size_t f = wanted[k];
                streams[k].append(packet.data() + begin[f], size[f]);
                streams[k].decode(total, columns[k]);
                ready = std::min<std::uint64_t>(ready, columns[k].size());
            }
            emit(ready);
        } else if (type != index_packet && type != empty_packet) {
            pages.fail(physical, "unknown packet type " + std::to_string(type));
        }
        at += length;
    }
}

}  // namespace tlsmon
