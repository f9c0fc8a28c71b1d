#pragma once
// What the report's plots share (report/plots.cpp, report_model_plot.cpp): data and
// scripts written beside each other, and gnuplot (Debian `gnuplot-nox`, pngcairo) run on a
// script in its own folder.
#include <filesystem>
#include <string>

namespace tlsmon::report {

// The whole file; throws Error when it cannot be written.
void write_text(const std::filesystem::path& path, const std::string& text);

// A gnuplot string literal (single quotes; a quote doubled).
std::string gnuplot_quoted(const std::string& s);

// A name as a file name's part: every character but letters and digits as '_'.
std::string safe_name(const std::string& s);

bool have_gnuplot();

// Runs gnuplot on `script` from the script's folder (it reads its data files there); its
// messages go to `log`. True when `png` was written (an old one is removed first).
bool run_gnuplot(const std::filesystem::path& script, const std::filesystem::path& png,
                 const std::filesystem::path& log);

}  // namespace tlsmon::report
