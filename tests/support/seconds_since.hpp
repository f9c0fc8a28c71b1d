#pragma once
// Wall seconds since a steady-clock instant: the stage timings of the tests and the benches.
#include <chrono>

namespace tlsmon::test {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace tlsmon::test
