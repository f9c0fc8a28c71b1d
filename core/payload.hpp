#pragma once
// Little-endian byte payloads of what the reference cache keeps: plain numbers and arrays of
// them, written in order and read back in the same order. A payload that ends early or has
// bytes left over is corrupt (an Error), never silently padded.
#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/error.hpp"

namespace tlsmon {

static_assert(std::endian::native == std::endian::little, "payloads are little-endian");

class PayloadWriter {
  public:
    template <class T>
    void put(const T& value) {
        static_assert(std::is_trivially_copyable_v<T>);
        bytes_.append(reinterpret_cast<const char*>(&value), sizeof value);
    }
    template <class T>
    void put_array(const std::vector<T>& values) {
        static_assert(std::is_trivially_copyable_v<T>);
        put<std::uint64_t>(values.size());
        bytes_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    }
    std::string take() { return std::move(bytes_); }

  private:
    std::string bytes_;
};

class PayloadReader {
  public:
    explicit PayloadReader(std::string_view bytes) : bytes_(bytes) {}

    template <class T>
    T get() {
        static_assert(std::is_trivially_copyable_v<T>);
        T value;
        std::memcpy(&value, take(sizeof value), sizeof value);
        return value;
    }
    template <class T>
    std::vector<T> get_array() {
        const auto n = get<std::uint64_t>();
        if (n > (bytes_.size() - at_) / sizeof(T)) corrupt("array longer than the payload");
        std::vector<T> values(n);
        std::memcpy(values.data(), take(n * sizeof(T)), n * sizeof(T));
        return values;
    }
    // Throws unless every byte was read.
    void finish() const {
        if (at_ != bytes_.size()) corrupt("bytes left over");
    }

  private:
    const char* take(std::size_t n) {
        if (n > bytes_.size() - at_) corrupt("ends early");
        const char* p = bytes_.data() + at_;
        at_ += n;
        return p;
    }
    [[noreturn]] void corrupt(const char* what) const {
        throw Error(std::string("reference cache payload: ") + what + " (at byte " +
                    std::to_string(at_) + " of " + std::to_string(bytes_.size()) + ")");
    }

    std::string_view bytes_;
    std::size_t at_ = 0;
};

}  // namespace tlsmon
