// The [[instrument]] tables: read with their defaults, matched against file names, errors
// naming the key and line.
#include <gtest/gtest.h>

#include "config/config.hpp"
#include "tests/support/config_text.hpp"

namespace tlsmon {
namespace {

using test::error_of;
using test::parse;

TEST(ConfigInstruments, ReadWithDefaultsAndMatchedByPattern) {
    const Config c = parse(
        "[[instrument]]\nname = \"backpack\"\nkind = \"pls\"\nrange_sigma = 0.015\n"
        "pattern = \"pls_*.ply\"\n"
        "[[instrument]]\nname = \"van\"\nkind = \"mls\"\npattern = \"mls_*\"\n"
        "[[instrument]]\nname = \"by-hand\"\n");
    ASSERT_EQ(c.instruments.size(), 3u);
    EXPECT_EQ(c.instruments[0].kind, InstrumentKind::pls);
    EXPECT_DOUBLE_EQ(c.instruments[0].range_sigma, 0.015);
    EXPECT_EQ(c.instruments[1].kind, InstrumentKind::mls);
    EXPECT_DOUBLE_EQ(c.instruments[1].range_sigma, 0.02);
    EXPECT_EQ(c.instruments[2].kind, InstrumentKind::pls);
    EXPECT_TRUE(c.instruments[2].pattern.empty());
    EXPECT_EQ(instrument_for(c.instruments, "pls_20261202T0800Z.ply"), &c.instruments[0]);
    EXPECT_EQ(instrument_for(c.instruments, "mls_deck.e57"), &c.instruments[1]);
    // The station's scans and a name only like the pattern are not campaigns; an instrument
    // without a pattern never takes a file.
    EXPECT_EQ(instrument_for(c.instruments, "pier_20261202T080000Z.ptx"), nullptr);
    EXPECT_EQ(instrument_for(c.instruments, "xpls_a.ply"), nullptr);
    EXPECT_EQ(instrument_for(c.instruments, "pls_a.ptx"), nullptr);
    EXPECT_EQ(instrument_for(c.instruments, ""), nullptr);
    EXPECT_TRUE(parse("").instruments.empty());
    bool described = false;
    for (const auto& line : describe(c))
        described = described || line ==
                                     "instrument \"backpack\": kind = pls, range_sigma = "
                                     "0.015, pattern = \"pls_*.ply\"";
    EXPECT_TRUE(described);
}

TEST(ConfigInstruments, BadTablesNameKeyAndLine) {
    const std::string kind = error_of("[[instrument]]\nname = \"a\"\nkind = \"drone\"\n");
    EXPECT_NE(kind.find("site.toml:3"), std::string::npos) << kind;
    EXPECT_NE(kind.find("'drone' is not one of: tls, pls, mls"), std::string::npos) << kind;
    const std::string twice =
        error_of("[[instrument]]\nname = \"a\"\n[[instrument]]\nname = \"a\"\n");
    EXPECT_NE(twice.find("defined twice"), std::string::npos) << twice;
    const std::string nameless = error_of("[[instrument]]\nkind = \"pls\"\n");
    EXPECT_NE(nameless.find("needs a name"), std::string::npos) << nameless;
    const std::string sigma = error_of("[[instrument]]\nname = \"a\"\nrange_sigma = -0.01\n");
    EXPECT_NE(sigma.find("range_sigma"), std::string::npos) << sigma;
    const std::string folder = error_of("[[instrument]]\nname = \"a\"\npattern = \"x/*.ply\"\n");
    EXPECT_NE(folder.find("no '/'"), std::string::npos) << folder;
    const std::string same = error_of(
        "[[instrument]]\nname = \"a\"\npattern = \"p*\"\n[[instrument]]\nname = \"b\"\n"
        "pattern = \"p*\"\n");
    EXPECT_NE(same.find("same pattern"), std::string::npos) << same;
    const std::string unknown = error_of("[[instrument]]\nname = \"a\"\nsigma = 0.01\n");
    EXPECT_NE(unknown.find("sigma"), std::string::npos) << unknown;
}

// [campaign]: how every instrument's campaigns are compared, with the instrument's own noise.
TEST(ConfigInstruments, CampaignKeysMakeTheComparisonsParameters) {
    const Config c = parse(
        "[campaign]\nmetric = \"point-to-point\"\nc2c = \"nearest-point\"\nradius = 0.15\n"
        "thinning = 0\nmin_planar_share = 0.3\nalpha = 0.01\nremove_ground = false\n"
        "[[instrument]]\nname = \"van\"\nkind = \"mls\"\nrange_sigma = 0.03\n");
    const CampaignParameters p = campaign_parameters(c.campaign, c.instruments.at(0).range_sigma);
    EXPECT_EQ(p.icp.metric, campaign::IcpMetric::point_to_point);
    EXPECT_EQ(p.c2c, campaign::C2cModel::nearest_point);
    EXPECT_DOUBLE_EQ(p.verticality.radius, 0.15);
    EXPECT_DOUBLE_EQ(p.surface.plane_radius, 0.15);
    EXPECT_DOUBLE_EQ(p.thinning, 0);
    EXPECT_DOUBLE_EQ(p.min_planar_share, 0.3);
    EXPECT_DOUBLE_EQ(p.alpha, 0.01);
    EXPECT_FALSE(p.remove_ground);
    EXPECT_DOUBLE_EQ(p.range_sigma, 0.03);
    // The defaults are the comparison's own.
    const CampaignParameters d = campaign_parameters(parse("").campaign, 0.02);
    const CampaignParameters own;
    EXPECT_EQ(d.icp.metric, own.icp.metric);
    EXPECT_DOUBLE_EQ(d.thinning, own.thinning);
    EXPECT_EQ(d.registration_points, own.registration_points);
    EXPECT_DOUBLE_EQ(d.min_planar_share, own.min_planar_share);
    EXPECT_DOUBLE_EQ(d.min_overlap, own.min_overlap);
    EXPECT_DOUBLE_EQ(d.surface.max_distance, own.surface.max_distance);
    EXPECT_DOUBLE_EQ(d.alpha, own.alpha);

    const std::string metric = error_of("[campaign]\nmetric = \"closest\"\n");
    EXPECT_NE(metric.find("'closest' is not one of"), std::string::npos) << metric;
    const std::string alpha = error_of("[campaign]\nalpha = 0.7\n");
    EXPECT_NE(alpha.find("alpha"), std::string::npos) << alpha;
    const std::string few = error_of("[campaign]\nmin_segment_points = 10\n");
    EXPECT_NE(few.find("min_pairs"), std::string::npos) << few;
}

}  // namespace
}  // namespace tlsmon
