#pragma once
// Seeded, platform-independent random numbers for the measurement model. Every column of a
// scan has its own generator seeded from (seed, epoch, column), so a parallel render gives
// the same bytes as a serial one, on any standard library (std::normal_distribution is
// implementation-defined; the polar method over SplitMix64 is not).
#include <cmath>
#include <cstdint>

namespace tlsmon::sim {

// SplitMix64 finaliser (Steele, Lea & Flood 2014): a bijective 64-bit mixer.
constexpr std::uint64_t mix64(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

constexpr std::uint64_t hash_combine(std::uint64_t a, std::uint64_t b) {
    return mix64(a ^ mix64(b + 0x632be59bd9b4e019ULL));
}

class Rng {
  public:
    explicit Rng(std::uint64_t seed) : state_(mix64(seed)) {}

    std::uint64_t next() {
        state_ += 0x9e3779b97f4a7c15ULL;
        return mix64(state_);
    }
    // Uniform in (0, 1): 53 random bits, never 0 (log is safe).
    double uniform() { return (static_cast<double>(next() >> 11) + 0.5) * 0x1.0p-53; }
    // Standard normal by Marsaglia's polar method (Box–Muller without trigonometry); the
    // second value is kept for the next call.
    double normal() {
        if (has_spare_) {
            has_spare_ = false;
            return spare_;
        }
        double u, v, s;
        do {
            u = 2.0 * uniform() - 1.0;
            v = 2.0 * uniform() - 1.0;
            s = u * u + v * v;
        } while (s >= 1.0 || s == 0.0);
        const double f = std::sqrt(-2.0 * std::log(s) / s);
        spare_ = v * f;
        has_spare_ = true;
        return u * f;
    }

  private:
    std::uint64_t state_;
    double spare_ = 0.0;
    bool has_spare_ = false;
};

}  // namespace tlsmon::sim
