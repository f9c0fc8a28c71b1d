#include "pipeline/stored_area_vectors.hpp"

#include <cmath>

namespace tlsmon {

double StoredAreaVector::lod95_along(const Eigen::Vector3d& e) const {
    return 1.96 * std::sqrt(e.cwiseAbs2().dot(sigma.cwiseAbs2()));
}

std::vector<StoredAreaVector> read_area_vectors(const EpochDatabase& db, EpochId epoch) {
    std::array<std::vector<float>, 9> a;
    for (std::size_t c = 0; c < a.size(); ++c) {
        auto array = db.series().core_point_array(epoch, kAreaVectorArrays[c]);
        if (!array) return {};
        a[c] = std::move(array->values);
        if (a[c].size() != a[0].size()) return {};
    }
    std::vector<StoredAreaVector> out;
    for (std::size_t k = 0; k < a[0].size(); ++k) {
        const auto v = [&](std::size_t c) {
            return Eigen::Vector3d(a[c][k], a[c + 1][k], a[c + 2][k]);
        };
        const StoredAreaVector area{v(0), v(3), v(6)};
        // An area without a vector has NaN there.
        if (area.centre.allFinite() && area.displacement.allFinite() && area.sigma.allFinite())
            out.push_back(area);
    }
    return out;
}

}  // namespace tlsmon
