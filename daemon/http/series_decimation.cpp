#include "daemon/http/series_decimation.hpp"

#include <algorithm>

namespace tlsmon {

std::vector<std::size_t> min_max_decimation(const std::vector<std::int64_t>& times,
                                            const std::vector<double>& values, std::int64_t from,
                                            std::int64_t to, std::size_t buckets) {
    const std::size_t n = times.size();
    std::vector<std::size_t> kept;
    if (buckets == 0 || n <= 2 * buckets || to <= from) {
        kept.resize(n);
        for (std::size_t i = 0; i < n; ++i) kept[i] = i;
        return kept;
    }
    const double span = static_cast<double>(to - from);
    std::size_t i = 0;
    while (i < n) {
        const auto bucket_of = [&](std::size_t k) {
            const double f = static_cast<double>(times[k] - from) / span;
            return std::min(buckets - 1, static_cast<std::size_t>(std::max(0.0, f) *
                                                                  static_cast<double>(buckets)));
        };
        const std::size_t b = bucket_of(i);
        std::size_t lo = i, hi = i;
        std::size_t j = i + 1;
        for (; j < n && bucket_of(j) == b; ++j) {
            if (values[j] < values[lo]) lo = j;
            if (values[j] > values[hi]) hi = j;
        }
        kept.push_back(std::min(lo, hi));
        if (hi != lo) kept.push_back(std::max(lo, hi));
        i = j;
    }
    return kept;
}

}  // namespace tlsmon
