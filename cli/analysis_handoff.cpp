// The measuring commands of the `tlsmon` program: each hands the whole command line over to
// tlsmon-analysis (the same command line, linked with PCL and OpenCV), which replaces this
// process. The process id stays the same, so systemd's notifications and a supervisor's
// signals reach the daemon that `tlsmon run` started.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

#include "cli/commands.hpp"
#include "cli/program_arguments.hpp"

namespace tlsmon {
namespace {

namespace fs = std::filesystem;

// Beside this program (the build folder, or /usr/local/bin after deploy/install.sh), else
// where CMake's `install` puts helper programs (PREFIX/libexec/tlsmon).
std::vector<fs::path> analysis_program_candidates() {
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return {};
    const fs::path folder = self.parent_path();
    return {folder / "tlsmon-analysis",
            folder.parent_path() / "libexec" / "tlsmon" / "tlsmon-analysis"};
}

int hand_over_to_analysis() {
    char** argv = program_arguments();
    const auto candidates = analysis_program_candidates();
    std::fflush(nullptr);
    int error = ENOENT;
    for (const auto& program : candidates) {
        ::execv(program.c_str(), argv);
        error = errno;  // only reached when the exec failed
    }
    std::string looked;
    for (const auto& program : candidates) looked += "\n  " + program.string();
    std::fprintf(stderr,
                 "tlsmon: this command runs in tlsmon-analysis, which could not be started (%s); "
                 "looked for:%s\n",
                 std::strerror(error), looked.c_str());
    return 1;
}

}  // namespace

int run_notify_test(const NotifyTestOptions&) {
    return hand_over_to_analysis();
}
int run_ingest(const RunOptions&) {
    return hand_over_to_analysis();
}
int run_simulate(const SimulateOptions&) {
    return hand_over_to_analysis();
}
int run_register(const RegisterOptions&) {
    return hand_over_to_analysis();
}
int run_m3c2(const M3c2Options&) {
    return hand_over_to_analysis();
}
int run_pbm3c2(const PbM3c2Options&) {
    return hand_over_to_analysis();
}
int run_primitives(const PrimitivesOptions&) {
    return hand_over_to_analysis();
}
int run_vectors(const VectorsOptions&) {
    return hand_over_to_analysis();
}
int run_campaign_compare(const CampaignCompareOptions&) {
    return hand_over_to_analysis();
}
int run_campaign_add(const CampaignAddOptions&) {
    return hand_over_to_analysis();
}
int run_keypoints(const KeypointsOptions&) {
    return hand_over_to_analysis();
}
int run_report(const ReportOptions&) {
    return hand_over_to_analysis();
}
int run_calibration(const CalibrationOptions&) {
    return hand_over_to_analysis();
}
int run_demo(const DemoOptions&) {
    return hand_over_to_analysis();
}
int run_central_admin(const CentralAdminOptions&) {
    return hand_over_to_analysis();
}
int run_fleet(const FleetOptions&) {
    return hand_over_to_analysis();
}

}  // namespace tlsmon
