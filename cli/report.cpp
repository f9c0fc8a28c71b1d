// `tlsmon report --database DB [--truth DIR] --out DIR`: a run of the daemon — registration,
// zones, alarms — as Markdown, CSV and PNG plots (report/); with the simulator's truth files
// scored against them, without (a real site) in the run's own figures.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <vector>

#include "cli/commands.hpp"
#include "core/error.hpp"
#include "core/utc_time.hpp"
#include "report/output.hpp"
#include "storage/storage_error.hpp"

namespace tlsmon {

int run_report(const ReportOptions& o) {
    namespace fs = std::filesystem;
    try {
        if (!fs::exists(o.database)) throw Error("no database at " + o.database);
        const auto truth = o.truth.empty() ? std::vector<report::TruthEpoch>{}
                                           : report::read_truth_folder(o.truth);
        ReadOptions window_options;
        window_options.from = o.from;
        window_options.to = o.to;
        const TimeRange window = time_range(window_options);
        const report::RunData run = report::read_run(fs::path(o.database), window);
        const report::RunReport r = report::analyse(run, truth, o.truth);
        const fs::path out(o.out);
        fs::create_directories(out);
        report::ReportFiles files;
        report::write_csv(r, out, files);
        report::draw_plots(r, out, files);
        files.markdown = out / "report.md";
        const std::string md = report::markdown(
            r, files,
            {o.config.empty() ? fs::path() : fs::path(o.config), o.modbus_port,
             window.from || window.to
                 ? (window.from ? format_utc(*window.from) : std::string("the start")) + " to " +
                       (window.to ? format_utc(*window.to) : std::string("now"))
                 : std::string()});
        std::ofstream f(files.markdown, std::ios::binary | std::ios::trunc);
        f << md;
        f.close();
        if (!f) throw Error("cannot write " + files.markdown.string());
        for (const auto& line : report::summary_lines(r)) std::cout << "  " << line << '\n';
        std::cout << "report: " << files.markdown.string() << " (";
        for (std::size_t i = 0; i < files.csv.size(); ++i) {
            std::cout << (i ? ", " : "") << files.csv[i].filename().string();
        }
        for (const auto& p : files.plots) std::cout << ", " << p.filename().string();
        std::cout << ")" << std::endl;
        for (const auto& n : files.notes) std::cout << "  note: " << n << '\n';
    } catch (const std::exception& e) {
        std::cerr << "tlsmon report: " << e.what() << '\n';
        return 1;
    }
    return 0;
}

}  // namespace tlsmon
