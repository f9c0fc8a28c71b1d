#pragma once
// The physical layer of an E57 file (ASTM E2807-11 §8): a 48-byte file header, then
// 1024-byte pages, each 1020 bytes of payload followed by the CRC-32C of that payload
// stored big-endian. Binary sections and the XML section are addressed in "logical"
// bytes (payload only); this class maps them onto the pages and checks every page's
// checksum the first time it is read.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace tlsmon {

inline constexpr std::uint64_t e57_page_size = 1024;
inline constexpr std::uint64_t e57_page_payload = 1020;

struct E57Header {
    std::uint32_t major_version = 0;
    std::uint32_t minor_version = 0;
    std::uint64_t physical_length = 0;
    std::uint64_t xml_physical_offset = 0;
    std::uint64_t xml_logical_length = 0;
    std::uint64_t page_size = 0;
};

class E57Pages {
  public:
    // Validates the header and the file length; throws FormatError naming `file` and the
    // byte. The bytes (usually a MappedFile) must outlive this object.
    E57Pages(const char* data, std::uint64_t size, const std::filesystem::path& file);

    const E57Header& header() const { return header_; }
    const std::filesystem::path& path() const { return path_; }
    std::uint64_t physical_size() const { return size_; }
    std::uint64_t logical_size() const { return size_ / e57_page_size * e57_page_payload; }

    static std::uint64_t to_logical(std::uint64_t physical) {
        return physical / e57_page_size * e57_page_payload + physical % e57_page_size;
    }
    static std::uint64_t to_physical(std::uint64_t logical) {
        return logical / e57_page_payload * e57_page_size + logical % e57_page_payload;
    }
    // True when `physical` is a payload byte (not inside a page's checksum).
    static bool is_payload(std::uint64_t physical) {
        return physical % e57_page_size < e57_page_payload;
    }

    // Copies n logical bytes starting at logical offset `logical`, page by page, checking
    // each page's CRC-32C once. Throws when the range runs past the end of the file.
    void read(std::uint64_t logical, std::uint64_t n, void* out);

    // The XML section as text (bounded by the file size, checked by the constructor).
    std::string read_xml();
    // Physical offset of byte k of the XML section, for error messages.
    std::uint64_t xml_byte(std::uint64_t k) const {
        return to_physical(to_logical(header_.xml_physical_offset) + k);
    }

    [[noreturn]] void fail(std::uint64_t physical, const std::string& what) const;

  private:
    void check_page(std::uint64_t page);

    const char* data_;
    std::uint64_t size_;
    std::filesystem::path path_;
    E57Header header_;
    std::vector<bool> checked_;
};

}  // namespace tlsmon
