#pragma once
// CSV text as rows of cells (RFC 4180 quoting: a quoted cell may hold commas and doubled
// quotes; one record per line).
#include <sstream>
#include <string>
#include <vector>

namespace tlsmon::test {

inline std::vector<std::vector<std::string>> csv_cells(const std::string& text) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        std::vector<std::string> cells(1);
        bool quoted = false;
        for (std::size_t i = 0; i < line.size(); ++i) {
            const char ch = line[i];
            if (quoted) {
                if (ch == '"' && i + 1 < line.size() && line[i + 1] == '"') {
                    cells.back() += '"';
                    ++i;
                } else if (ch == '"') {
                    quoted = false;
                } else {
                    cells.back() += ch;
                }
            } else if (ch == '"') {
                quoted = true;
            } else if (ch == ',') {
                cells.emplace_back();
            } else {
                cells.back() += ch;
            }
        }
        if (line.empty()) cells.clear();
        rows.push_back(cells);
    }
    return rows;
}

}  // namespace tlsmon::test
