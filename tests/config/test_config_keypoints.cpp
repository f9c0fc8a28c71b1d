// The [keypoints] section: what the file says, what the stage receives (pipeline_config:
// the zones too), and each mistake named by file, line, column and key.
#include <gtest/gtest.h>

#include "algorithms/keypoints/feature_parameters.hpp"
#include "config/config.hpp"
#include "tests/support/config_text.hpp"

namespace tlsmon {
namespace {

using test::error_of;
using test::parse;

TEST(ConfigKeypoints, SectionAndZonesReachTheStage) {
    const Config c = parse(R"(
[[zone]]
name = "south"
min = [2, 44.5, 0]
max = [17, 45.5, 40]

[keypoints]
detector = "kaze"
detector_threshold = 0.002
segments = "bands"
band_width_deg = 2.5
max_incidence_deg = 60
refine = false
model_quantities = ["keypoint_dz_m"]
)");
    const PipelineConfig p = pipeline_config(c);
    EXPECT_EQ(p.keypoints.detector, "kaze");
    EXPECT_EQ(p.keypoints.descriptor, "brisk");
    EXPECT_EQ(p.keypoints.detector_threshold, 0.002);
    EXPECT_EQ(keypoints::features_of(p.keypoints).detector_threshold, 0.002);
    EXPECT_EQ(p.keypoints.segments, KeypointSegments::bands);
    EXPECT_EQ(p.keypoints.band_width_deg, 2.5);
    EXPECT_EQ(p.keypoints.max_incidence_deg, 60);
    EXPECT_FALSE(p.keypoints.refine);
    EXPECT_EQ(p.keypoints.model_quantities, std::vector<std::string>{"keypoint_dz_m"});
    ASSERT_EQ(p.keypoints.zones.size(), 1u);
    EXPECT_TRUE(p.keypoints.zones[0].contains({5, 45, 10}));
}

TEST(ConfigKeypoints, TheStationsScannerModelReachesPlanesAndKeypoints) {
    // One stochastic model for the site ([station]); the stages take it from there.
    const Config c = parse(R"(
[station]
range_sigma_a = 0.002
range_sigma_b_ppm = 20
angular_sigma_arcsec = 5

[keypoints]
window_m = 0.05
)");
    const PipelineConfig p = pipeline_config(c);
    EXPECT_EQ(p.keypoints.noise.range_sigma_a, 0.002);
    EXPECT_EQ(p.keypoints.noise.range_sigma_b_ppm, 20);
    EXPECT_EQ(p.keypoints.noise.angular_sigma_arcsec, 5);
    EXPECT_EQ(p.registration.planes.noise.range_sigma_a, 0.002);
    EXPECT_EQ(p.registration.planes.detection().noise.angular_sigma_arcsec, 5);
    EXPECT_EQ(p.keypoints.window_m, 0.05);
    EXPECT_EQ(pipeline_config(parse("")).keypoints.window_m, 0.02);
    // The model's old place is named in the error, not only "unknown key".
    const std::string moved = error_of("[registration]\nplane_range_sigma_a = 0.002\n");
    EXPECT_NE(moved.find("key 'registration.plane_range_sigma_a': moved to "
                         "station.range_sigma_a"),
              std::string::npos)
        << moved;
    EXPECT_NE(error_of("[station]\nrange_sigma_a = -1\n").find("key 'station.range_sigma_a'"),
              std::string::npos);
    EXPECT_NE(error_of("[keypoints]\nwindow_m = 2\n").find("key 'keypoints.window_m'"),
              std::string::npos);
}

TEST(ConfigKeypoints, MistakesNameFileLineAndKey) {
    EXPECT_EQ(error_of("[keypoints]\ndetector = \"surf\"\n")
                  .rfind("site.toml:2:12: key 'keypoints.detector': ", 0),
              0u)
        << error_of("[keypoints]\ndetector = \"surf\"\n");
    EXPECT_NE(error_of("[keypoints]\ndescriptor = \"kaze\"\n")
                  .find("site.toml:2:14: key 'keypoints.descriptor': "),
              std::string::npos)
        << error_of("[keypoints]\ndescriptor = \"kaze\"\n");
    EXPECT_NE(error_of("[keypoints]\nsegments = \"rows\"\n").find("key 'keypoints.segments'"),
              std::string::npos);
    EXPECT_NE(error_of("[keypoints]\nwindow_deg = 0\n")
                  .find("site.toml:2:14: key 'keypoints.window_deg'"),
              std::string::npos)
        << error_of("[keypoints]\nwindow_deg = 0\n");
    EXPECT_NE(error_of("[keypoints]\ndetector_threshold = 0\n")
                  .find("site.toml:2:22: key 'keypoints.detector_threshold'"),
              std::string::npos)
        << error_of("[keypoints]\ndetector_threshold = 0\n");
    EXPECT_NE(error_of("[keypoints]\nmodel_quantities = [\"m3c2_mean_m\"]\n")
                  .find("key 'keypoints.model_quantities': 'm3c2_mean_m' is not a keypoint"),
              std::string::npos)
        << error_of("[keypoints]\nmodel_quantities = [\"m3c2_mean_m\"]\n");
    EXPECT_NE(
        error_of("[keypoints]\nthreshold = 1\n").find("key 'keypoints.threshold': unknown key"),
        std::string::npos);
}

}  // namespace
}  // namespace tlsmon
