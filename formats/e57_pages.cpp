#include "formats/e57_pages.hpp"

#include <boost/crc.hpp>
#include <cstring>
#include <sstream>

#include "formats/format_error.hpp"

namespace tlsmon {

namespace {

// CRC-32C (Castagnoli, reflected polynomial 0x82F63B78), the page checksum of E2807 §8.
using Crc32c = boost::crc_optimal<32, 0x1EDC6F41, 0xFFFFFFFF, 0xFFFFFFFF, true, true>;

std::uint32_t crc32c_portable(const char* p, std::size_t n) {
    Crc32c crc;
    crc.process_bytes(p, n);
    return crc.checksum();
}

#if defined(__x86_64__)
// The SSE4.2 crc32 instruction computes exactly CRC-32C, 8 bytes at a time: the checksum
// of every page read is otherwise the largest cost of reading a file.
__attribute__((target("sse4.2"))) std::uint32_t crc32c_sse42(const char* p, std::size_t n) {
    std::uint64_t c = 0xFFFFFFFFu;
    for (; n >= 8; n -= 8, p += 8) {
        std::uint64_t v;
        std::memcpy(&v, p, 8);
        c = __builtin_ia32_crc32di(c, v);
    }
    auto c32 = static_cast<std::uint32_t>(c);
    for (; n > 0; --n, ++p) c32 = __builtin_ia32_crc32qi(c32, static_cast<unsigned char>(*p));
    return c32 ^ 0xFFFFFFFFu;
}

std::uint32_t crc32c(const char* p, std::size_t n) {
    static const bool sse42 = __builtin_cpu_supports("sse4.2");
    return sse42 ? crc32c_sse42(p, n) : crc32c_portable(p, n);
}
#else
std::uint32_t crc32c(const char* p, std::size_t n) {
    return crc32c_portable(p, n);
}
#endif

std::uint64_t le64(const char* p) {
    std::uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(p[i]);
    return v;
}
std::uint32_t le32(const char* p) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(p[i]);
    return v;
}
std::uint32_t be32(const char* p) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(p[i]);
    return v;
}

std::string hex(std::uint32_t v) {
    std::ostringstream s;
    s << "0x" << std::hex << v;
    return s.str();
}

}  // namespace

E57Pages::E57Pages(const char* data, std::uint64_t size, const std::filesystem::path& file)
    : data_(data), size_(size), path_(file) {
    const char* d = data;
    if (size >= 8 && std::memcmp(d, "ASTM-E57", 8) != 0)
        fail(0, "not an E57 file (no ASTM-E57 signature)");
    if (size == 0 || size % e57_page_size != 0)
        fail(size, "file length " + std::to_string(size) + " bytes is not a multiple of the " +
                       std::to_string(e57_page_size) + "-byte E57 page (truncated file?)");
    checked_.assign(size / e57_page_size, false);
    check_page(0);  // the header lives in page 0: trust it only after its checksum

    // E2807 §8.2 file header: signature, version, lengths and offsets, little-endian.
    header_.major_version = le32(d + 8);
    header_.minor_version = le32(d + 12);
    header_.physical_length = le64(d + 16);
    header_.xml_physical_offset = le64(d + 24);
    header_.xml_logical_length = le64(d + 32);
    header_.page_size = le64(d + 40);
    if (header_.major_version != 1)
        fail(8, "unsupported E57 major version " + std::to_string(header_.major_version));
    if (header_.page_size != e57_page_size)
        fail(40, "page size " + std::to_string(header_.page_size) + " is not 1024");
    if (header_.physical_length > size)
        fail(size, "truncated file: the header declares " +
                       std::to_string(header_.physical_length) + " bytes, the file has " +
                       std::to_string(size));
    if (header_.physical_length < size)
        fail(16, "the header declares " + std::to_string(header_.physical_length) +
                     " bytes but the file has " + std::to_string(size));
    const std::uint64_t xml = header_.xml_physical_offset;
    if (xml < 48 || xml >= size || !is_payload(xml))
        fail(24, "XML section offset " + std::to_string(xml) + " is outside the file's payload");
    if (header_.xml_logical_length > logical_size() - to_logical(xml))
        fail(32, "XML section length " + std::to_string(header_.xml_logical_length) +
                     " runs past the end of the file");
}

void E57Pages::fail(std::uint64_t physical, const std::string& what) const {
    throw_at_byte(path_, physical, what);
}

void E57Pages::check_page(std::uint64_t page) {
    if (checked_[page]) return;
    const char* p = data_ + page * e57_page_size;
    const std::uint32_t computed = crc32c(p, e57_page_payload);
    const std::uint32_t stored = be32(p + e57_page_payload);
    if (computed != stored)
        fail(page * e57_page_size + e57_page_payload,
             "bad checksum of page " + std::to_string(page) + ": stored " + hex(stored) +
                 ", computed CRC-32C " + hex(computed));
    checked_[page] = true;
}

void E57Pages::read(std::uint64_t logical, std::uint64_t n, void* out) {
    auto* dst = static_cast<char*>(out);
    if (logical > logical_size() || n > logical_size() - logical)
        fail(size_, "truncated file: needs logical bytes up to " + std::to_string(logical + n) +
                        ", the file holds " + std::to_string(logical_size()));
    while (n > 0) {
        const std::uint64_t page = logical / e57_page_payload;
        const std::uint64_t in_page = logical % e57_page_payload;
        const std::uint64_t chunk = std::min(n, e57_page_payload - in_page);
        check_page(page);
        std::memcpy(dst, data_ + page * e57_page_size + in_page, chunk);
        dst += chunk;
        logical += chunk;
        n -= chunk;
    }
}

std::string E57Pages::read_xml() {
    std::string xml(header_.xml_logical_length, '\0');
    read(to_logical(header_.xml_physical_offset), xml.size(), xml.data());
    return xml;
}

}  // namespace tlsmon
