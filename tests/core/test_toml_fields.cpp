// TomlFields: each getter fills a value or names file:line:column and the key.
#include <gtest/gtest.h>

#include <array>

#include "core/toml_fields.hpp"

namespace tlsmon {
namespace {

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

TEST(TomlFields, ReadsValuesOfEachType) {
    const auto doc = parse_toml_string(
        "flag = true\nname = \"north\"\nratio = 0.25\ncount = 7\nwait = \"15min\"\n"
        "xs = [1, 2.5, -3]\n",
        "t.toml");
    TomlFields f(doc, "t.toml");
    bool flag = false;
    std::string name;
    double ratio = 0;
    int count = 0;
    double wait = 0;
    std::vector<double> xs;
    f.get("flag", flag);
    f.get("name", name);
    f.get("ratio", ratio, 0.0, 1.0);
    f.get("count", count, 0, 10);
    f.get_seconds("wait", wait, 0, 86400);
    f.get("xs", xs);
    f.reject_unknown_keys();
    EXPECT_TRUE(flag);
    EXPECT_EQ(name, "north");
    EXPECT_DOUBLE_EQ(ratio, 0.25);
    EXPECT_EQ(count, 7);
    EXPECT_DOUBLE_EQ(wait, 900.0);
    EXPECT_EQ(xs, (std::vector<double>{1, 2.5, -3}));
}

TEST(TomlFields, AbsentKeyKeepsDefault) {
    const auto doc = parse_toml_string("", "t.toml");
    TomlFields f(doc, "t.toml");
    int count = 42;
    f.get("count", count, 0, 100);
    EXPECT_EQ(count, 42);
}

TEST(TomlFields, WrongTypeNamesKeyAndLine) {
    const auto doc = parse_toml_string("a = 1\n\ncount = \"seven\"\n", "t.toml");
    TomlFields f(doc, "t.toml");
    int count = 0;
    const std::string e = error_of([&] { f.get("count", count, 0, 10); });
    EXPECT_NE(e.find("t.toml:3:"), std::string::npos) << e;
    EXPECT_NE(e.find("key 'count'"), std::string::npos) << e;
    EXPECT_NE(e.find("whole number"), std::string::npos) << e;
}

TEST(TomlFields, OutOfRangeNamesKeyLineAndRange) {
    const auto doc = parse_toml_string("[ingest]\nratio = 1.5\n", "t.toml");
    TomlFields root(doc, "t.toml");
    auto f = root.table("ingest");
    ASSERT_TRUE(f);
    double ratio = 0;
    const std::string e = error_of([&] { f->get("ratio", ratio, 0.0, 1.0); });
    EXPECT_NE(e.find("t.toml:2:"), std::string::npos) << e;
    EXPECT_NE(e.find("key 'ingest.ratio'"), std::string::npos) << e;
    EXPECT_NE(e.find("outside 0 .. 1"), std::string::npos) << e;
    EXPECT_DOUBLE_EQ(ratio, 0.0);
}

TEST(TomlFields, UnknownKeyIsRejectedWithItsLine) {
    const auto doc = parse_toml_string("name = \"a\"\nnmae = \"b\"\n", "t.toml");
    TomlFields f(doc, "t.toml");
    std::string name;
    f.get("name", name);
    const std::string e = error_of([&] { f.reject_unknown_keys(); });
    EXPECT_NE(e.find("t.toml:2:"), std::string::npos) << e;
    EXPECT_NE(e.find("key 'nmae'"), std::string::npos) << e;
    EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
}

TEST(TomlFields, ArrayOfStrings) {
    const auto doc = parse_toml_string(
        "names = [\"ptx\", \"e57\"]\nnone = []\n\nmixed = [\"a\", 2]\nplain = \"a\"\n", "t.toml");
    TomlFields f(doc, "t.toml");
    std::vector<std::string> names, none = {"default"}, absent = {"default"}, mixed = {"kept"};
    f.get("names", names);
    f.get("none", none);
    f.get("absent", absent);
    EXPECT_EQ(names, (std::vector<std::string>{"ptx", "e57"}));
    EXPECT_TRUE(none.empty());
    EXPECT_EQ(absent, (std::vector<std::string>{"default"}));
    std::string e = error_of([&] { f.get("mixed", mixed); });
    EXPECT_NE(e.find("t.toml:4:"), std::string::npos) << e;
    EXPECT_NE(e.find("key 'mixed'"), std::string::npos) << e;
    EXPECT_NE(e.find("expected an array of strings"), std::string::npos) << e;
    EXPECT_EQ(mixed, (std::vector<std::string>{"kept"}));
    std::vector<std::string> plain;
    e = error_of([&] { f.get("plain", plain); });
    EXPECT_NE(e.find("t.toml:5:"), std::string::npos) << e;
    EXPECT_NE(e.find("key 'plain'"), std::string::npos) << e;
    EXPECT_NE(e.find("expected an array of strings"), std::string::npos) << e;
    f.reject_unknown_keys();  // every key was asked for
}

TEST(TomlFields, ChoiceListsAllowedValues) {
    const auto doc = parse_toml_string("mode = \"copy\"\n", "t.toml");
    TomlFields f(doc, "t.toml");
    std::string mode = "move";
    const std::string e = error_of([&] { f.get_choice("mode", mode, {"move", "keep"}); });
    EXPECT_NE(e.find("'copy' is not one of: move, keep"), std::string::npos) << e;
    EXPECT_EQ(mode, "move");
}

enum class Mode { move, keep };
constexpr std::array<Named<Mode>, 2> kModes{{{Mode::move, "move"}, {Mode::keep, "keep"}}};

TEST(TomlFields, NamedChoiceBecomesItsEnumerator) {
    const auto doc = parse_toml_string(
        "mode = \"keep\"\nbad = \"copy\"\nmodes = [\"keep\", \"move\"]\ntwice = [\"keep\", "
        "\"keep\"]\n",
        "t.toml");
    TomlFields f(doc, "t.toml");
    Mode mode = Mode::move;
    f.get_choice("mode", mode, kModes);
    EXPECT_EQ(mode, Mode::keep);
    Mode absent = Mode::keep;
    f.get_choice("absent", absent, kModes);
    EXPECT_EQ(absent, Mode::keep);
    std::vector<Mode> modes;
    f.get_choices("modes", modes, kModes);
    EXPECT_EQ(modes, (std::vector{Mode::keep, Mode::move}));
    std::string e = error_of([&] { f.get_choice("bad", mode, kModes); });
    EXPECT_NE(e.find("t.toml:2:"), std::string::npos) << e;
    EXPECT_NE(e.find("'copy' is not one of: move, keep"), std::string::npos) << e;
    e = error_of([&] { f.get_choices("twice", modes, kModes); });
    EXPECT_NE(e.find("'keep' is listed twice"), std::string::npos) << e;
    EXPECT_EQ(name_of(Mode::keep, kModes), "keep");
}

TEST(TomlFields, UnopenableFileGivesTheSystemsReason) {
    std::string e = error_of([] { parse_toml_file("/nonexistent/site.toml"); });
    EXPECT_EQ(e, "cannot open /nonexistent/site.toml: No such file or directory");
    e = error_of([] { parse_toml_file("/"); });
    EXPECT_EQ(e, "cannot read /: Is a directory");
}

TEST(TomlFields, SyntaxErrorNamesLine) {
    const std::string e = error_of([] { parse_toml_string("a = 1\nb = = 2\n", "bad.toml"); });
    EXPECT_NE(e.find("bad.toml:2:"), std::string::npos) << e;
}

TEST(TomlFields, Durations) {
    EXPECT_DOUBLE_EQ(parse_duration_seconds("500ms"), 0.5);
    EXPECT_DOUBLE_EQ(parse_duration_seconds("30s"), 30.0);
    EXPECT_DOUBLE_EQ(parse_duration_seconds("2h"), 7200.0);
    EXPECT_DOUBLE_EQ(parse_duration_seconds("1d"), 86400.0);
    EXPECT_DOUBLE_EQ(parse_duration_seconds("90"), 90.0);
    EXPECT_THROW(parse_duration_seconds("5 fortnights"), ConfigError);
    EXPECT_THROW(parse_duration_seconds("-3s"), ConfigError);
}

}  // namespace
}  // namespace tlsmon
