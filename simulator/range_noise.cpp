#include "simulator/range_noise.hpp"

#include <algorithm>
#include <cmath>

namespace tlsmon::sim {

double range_sigma(const Noise& noise, double range, double signal) {
    if (noise.model == Noise::Model::constant) {
        return noise.range_a + noise.range_b_ppm * 1e-6 * range;
    }
    // A return weaker than ρ·cos α = 1e-4 gives no point anyway (min_return).
    return noise.signal_a + noise.signal_b_ppm * 1e-6 * range / std::sqrt(std::max(signal, 1e-4));
}

}  // namespace tlsmon::sim
