// The [[stable_region]] tables and the registration.icp keys: read, validated, errors naming
// the key and line.
#include <gtest/gtest.h>

#include "config/config.hpp"
#include "tests/support/config_text.hpp"

namespace tlsmon {
namespace {

using test::error_of;
using test::parse;

TEST(ConfigStableRegions, RegionsAndIcpKeysReachTheRegistration) {
    const Config c = parse(
        "[registration]\nicp = \"both\"\nicp_voxel_size = 0.2\nicp_max_iterations = 30\n"
        "[[stable_region]]\nname = \"abutment\"\nmin = [20, 55, -1]\nmax = [32, 65, 2.65]\n"
        "[[stable_region]]\nname = \"foundation-south\"\nmin = [-2.5, 40, -1]\nmax = [21.5, "
        "44.8, 0.55]\n");
    const RegistrationConfig r = pipeline_config(c).registration;
    EXPECT_EQ(r.icp.mode, IcpMode::both);
    EXPECT_DOUBLE_EQ(r.icp.voxel_size, 0.2);
    EXPECT_EQ(r.icp.max_iterations, 30);
    ASSERT_EQ(r.icp.regions.size(), 2u);
    EXPECT_EQ(r.icp.regions[1].name, "foundation-south");
    EXPECT_DOUBLE_EQ(r.icp.regions[1].max.y(), 44.8);
    EXPECT_TRUE(r.icp.regions[0].contains(Eigen::Vector3d(25, 60, 2.5)));
    EXPECT_FALSE(r.icp.regions[0].contains(Eigen::Vector3d(25, 60, 2.7)));
    EXPECT_EQ(parse("").icp.mode, IcpMode::off);
}

TEST(ConfigStableRegions, BadRegionsNameKeyAndLine) {
    const std::string inverted =
        error_of("[[stable_region]]\nname = \"a\"\nmin = [0, 0, 0]\nmax = [1, -1, 1]\n");
    EXPECT_NE(inverted.find("site.toml:4"), std::string::npos) << inverted;
    EXPECT_NE(inverted.find("max"), std::string::npos) << inverted;
    const std::string twice = error_of(
        "[[stable_region]]\nname = \"a\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"
        "[[stable_region]]\nname = \"a\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n");
    EXPECT_NE(twice.find("defined twice"), std::string::npos) << twice;
    const std::string two =
        error_of("[[stable_region]]\nname = \"a\"\nmin = [0, 0]\nmax = [1, 1, 1]\n");
    EXPECT_NE(two.find("three numbers"), std::string::npos) << two;
    const std::string none = error_of("[registration]\nicp = \"fallback\"\n");
    EXPECT_NE(none.find("stable_region"), std::string::npos) << none;
    EXPECT_NE(none.find("icp"), std::string::npos) << none;
    const std::string mode = error_of("[registration]\nicp = \"sometimes\"\n");
    EXPECT_NE(mode.find("'sometimes' is not one of"), std::string::npos) << mode;
}

}  // namespace
}  // namespace tlsmon
