#pragma once
// The cubic cell of side `size` holding a point, as one 64-bit key (21 bits per axis, ±2^20
// cells: ±1000 km at 1 m cells): the cells of the cluster-robust covariances.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>

namespace tlsmon {

inline std::uint64_t cell_key(const Eigen::Vector3d& p, double size) {
    std::uint64_t key = 0;
    for (int k = 0; k < 3; ++k) {
        const auto c = static_cast<std::int64_t>(std::floor(p(k) / size)) + (1 << 20);
        key = (key << 21) | (static_cast<std::uint64_t>(c) & 0x1FFFFF);
    }
    return key;
}

}  // namespace tlsmon
