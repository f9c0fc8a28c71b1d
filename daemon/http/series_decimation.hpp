#pragma once
// Decimation of a time series to a chart's pixel width: the time span is cut into equal
// buckets and each bucket keeps its lowest and its highest value (in time order), so a
// peak of one epoch survives at any zoom — the "min/max" reduction of plotting tools
// (unlike averaging or every k-th point, which hide a single-epoch spike).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tlsmon {

// `times` ascending. Indices of the points kept, ascending: all of them when there are at
// most 2 × `buckets`, else at most two per bucket over [from, to] (times outside are
// clamped into the first or last bucket).
std::vector<std::size_t> min_max_decimation(const std::vector<std::int64_t>& times,
                                            const std::vector<double>& values, std::int64_t from,
                                            std::int64_t to, std::size_t buckets);

}  // namespace tlsmon
