#include "cli/fleet_table.hpp"

#include <map>

namespace tlsmon {

namespace {

// Columns whose text is a number or a flag; every other is text.
enum class Kind { text, integer, real, flag };
const std::map<std::string, Kind> kKinds{{"epochs", Kind::integer},   {"entries", Kind::integer},
                                         {"n", Kind::integer},        {"value", Kind::real},
                                         {"uncertainty", Kind::real}, {"significant", Kind::flag}};

Cell cell(const std::optional<std::string>& text, Kind kind) {
    if (!text) return {};
    switch (kind) {
        case Kind::integer:
            return std::stoll(*text);
        case Kind::real:
            return std::stod(*text);
        case Kind::flag:
            return *text == "t";
        case Kind::text:
            break;
    }
    return *text;
}

}  // namespace

Table fleet_table(const PgResult& r, const std::string& quantity) {
    Table t;
    t.columns = r.columns;
    std::vector<Kind> kinds;
    for (const auto& c : r.columns) {
        const auto k = kKinds.find(c);
        kinds.push_back(k == kKinds.end() ? Kind::text : k->second);
        t.rounded_as.push_back((c == "value" || c == "uncertainty") ? quantity : "");
    }
    for (const auto& row : r.rows) {
        std::vector<Cell> cells;
        for (std::size_t i = 0; i < row.size(); ++i) cells.push_back(cell(row[i], kinds[i]));
        t.rows.push_back(std::move(cells));
    }
    return t;
}

}  // namespace tlsmon
