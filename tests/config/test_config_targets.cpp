// The [[target]] tables' sphere mount: read into the registration's targets, validated, errors
// naming the key and line.
#include <gtest/gtest.h>

#include "config/config.hpp"
#include "tests/support/config_text.hpp"

namespace tlsmon {
namespace {

using test::error_of;
using test::parse;

std::string sphere(const std::string& name, const std::string& extra) {
    return "[[target]]\nname = \"" + name + "\"\napproximate = [1, 2, 3]\n" + extra;
}

TEST(ConfigTargets, ASpheresMountIsBelowUnlessSaid) {
    const Config c = parse(sphere("T1", "") + sphere("T2", "mount = \"above\"\n") +
                           sphere("T3", "mount = \"none\"\nmount_cap_deg = 45\n"));
    const auto& t = pipeline_config(c).registration.targets;
    ASSERT_EQ(t.size(), 3u);
    EXPECT_EQ(t[0].mount, Eigen::Vector3d(0, 0, -1));
    EXPECT_DOUBLE_EQ(t[0].mount_cap_deg, 30.0);
    EXPECT_EQ(t[1].mount, Eigen::Vector3d(0, 0, 1));
    EXPECT_EQ(t[2].mount, Eigen::Vector3d::Zero());
    EXPECT_DOUBLE_EQ(t[2].mount_cap_deg, 45.0);
}

TEST(ConfigTargets, BadMountNamesKeyAndLine) {
    const std::string side = error_of(sphere("T1", "mount = \"side\"\n"));
    EXPECT_NE(side.find("site.toml:4"), std::string::npos) << side;
    EXPECT_NE(side.find("'side' is not one of"), std::string::npos) << side;
    const std::string cap = error_of(sphere("T1", "mount_cap_deg = 95\n"));
    EXPECT_NE(cap.find("mount_cap_deg"), std::string::npos) << cap;
    EXPECT_NE(cap.find("site.toml:4"), std::string::npos) << cap;
}

}  // namespace
}  // namespace tlsmon
