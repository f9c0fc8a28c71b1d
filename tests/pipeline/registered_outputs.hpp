#pragma once
// The windows' registration as the pipeline tests take it: a refused epoch is a test failure.
#include <gtest/gtest.h>

#include "tests/pipeline/simulated_windows.hpp"

namespace tlsmon::test {

inline std::optional<StageOutputs> registered_outputs(const RegistrationConfig& targets,
                                                      const ReferenceTargets& reference,
                                                      const WindowedEpoch& e0,
                                                      const WindowedEpoch& ei, int epoch) {
    std::string refused;
    auto o = registered_windows(targets, reference, e0, ei, refused);
    EXPECT_TRUE(o) << "epoch " << epoch << ": " << refused;
    return o;
}

}  // namespace tlsmon::test
