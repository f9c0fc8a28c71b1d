#pragma once
// The report of a run scored against the truth as files: CSV tables, PNG plots drawn by
// gnuplot, and one Markdown page that ties them together.
#include <filesystem>
#include <string>
#include <vector>

#include "report/analysis.hpp"

namespace tlsmon::report {

struct ReportContext {
    std::filesystem::path
        config;  // the daemon's configuration, for the example commands ("": none)
    int modbus_port = 1502;
    // The window the report was limited to, as "2026-03-01T00:00:00Z to open"; "": all epochs.
    std::string window;
};

struct ReportFiles {
    std::filesystem::path markdown;
    std::vector<std::filesystem::path> csv;
    std::vector<std::filesystem::path> plots;
    std::vector<std::string> notes;  // e.g. why a plot was not drawn
};

// registration.csv, zones.csv, alarms.csv into `out`.
void write_csv(const RunReport& report, const std::filesystem::path& out, ReportFiles& files);
// registration.png and zone_<name>.png, drawn by `gnuplot` (the plot data and scripts stay
// beside them under plots/); a missing gnuplot or a failed plot is a note, not an error.
void draw_plots(const RunReport& report, const std::filesystem::path& out, ReportFiles& files);
// keypoint_model_<quantity>.png: the last defined fit of d(t, z) of each modelled quantity
// in the database, with the segments' stored values (report_model_plot.cpp); a quantity never
// defined is a note.
void draw_keypoint_models(const std::filesystem::path& database,
                          const std::filesystem::path& plot_dir, ReportFiles& files);
// vectors_<zone>.png: the newest epoch's 3-D vectors (docs/vectors.md) of each zone's areas
// along the wall, with the truth's change at the same places when the run is scored
// (report/vector_plot.cpp); nothing when no epoch has vectors.
void draw_area_vectors(const RunReport& report, const std::filesystem::path& plot_dir,
                       ReportFiles& files);
// report.md
std::string markdown(const RunReport& report, const ReportFiles& files,
                     const ReportContext& context);

// The summary lines `tlsmon demo` prints at the end (a few lines of the Markdown's numbers).
std::vector<std::string> summary_lines(const RunReport& report);

}  // namespace tlsmon::report
