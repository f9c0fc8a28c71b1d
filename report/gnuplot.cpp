#include "report/gnuplot.hpp"

#include <cctype>
#include <cstdlib>
#include <fstream>

#include "core/error.hpp"

namespace tlsmon::report {

namespace fs = std::filesystem;

namespace {

// A shell word in single quotes.
std::string shell_quoted(const std::string& s) {
    std::string q = "'";
    for (const char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

}  // namespace

void write_text(const fs::path& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f << text;
    f.close();
    if (!f) throw Error("cannot write " + path.string());
}

std::string gnuplot_quoted(const std::string& s) {
    std::string q = "'";
    for (const char c : s) q += c == '\'' ? std::string("''") : std::string(1, c);
    return q + "'";
}

std::string safe_name(const std::string& s) {
    std::string out;
    for (const char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return out;
}

bool have_gnuplot() {
    return std::system("command -v gnuplot >/dev/null 2>&1") == 0;
}

// The script runs in its own folder (its data files are named from there), so the log — and
// the picture, which each script names — are given absolute: a relative path would be read
// from that folder instead of from where the command was run.
bool run_gnuplot(const fs::path& script, const fs::path& png, const fs::path& log) {
    std::error_code ec;
    fs::remove(png, ec);
    const std::string cmd = "cd " + shell_quoted(script.parent_path().string()) + " && gnuplot " +
                            shell_quoted(script.filename().string()) + " >" +
                            shell_quoted(fs::absolute(log).string()) + " 2>&1";
    return std::system(cmd.c_str()) == 0 && fs::exists(png) && fs::file_size(png) > 0;
}

}  // namespace tlsmon::report
