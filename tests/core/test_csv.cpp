#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/csv.hpp"

namespace tlsmon {
namespace {

TEST(Csv, FieldsAreQuotedOnlyWhenTheyMustBe) {
    EXPECT_EQ(csv_field("pier"), "pier");
    EXPECT_EQ(csv_field("a,b"), "\"a,b\"");
    EXPECT_EQ(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
    EXPECT_EQ(csv_field("two\nlines"), "\"two\nlines\"");
    EXPECT_EQ(csv_field("cr\r"), "\"cr\r\"");
    EXPECT_EQ(csv_field(""), "");
}

TEST(Csv, NumbersAtFullPrecisionAndMissingValuesEmpty) {
    for (double v : {0.1, 1.0 / 3.0, -7.546250499131459e-13, 1e300, 0.0012345678901234567}) {
        EXPECT_EQ(std::stod(csv_number(v)), v) << csv_number(v);
    }
    EXPECT_EQ(csv_number(0.5), "0.5");
    EXPECT_EQ(csv_number(0.0001), "0.0001");
    EXPECT_EQ(csv_number(-7.546250499131459e-13), "-7.546250499131459e-13");
    EXPECT_EQ(csv_number(std::numeric_limits<double>::quiet_NaN()), "");
    EXPECT_EQ(csv_number(std::numeric_limits<double>::infinity()), "");
}

TEST(Csv, ALineJoinsQuotedFields) {
    const std::vector<std::string> fields = {"zone", "a,b", "", "3"};
    EXPECT_EQ(csv_line(fields), "zone,\"a,b\",,3\n");
    std::string out = "x\n";
    append_csv_line(out, fields);
    EXPECT_EQ(out, "x\nzone,\"a,b\",,3\n");
}

}  // namespace
}  // namespace tlsmon
