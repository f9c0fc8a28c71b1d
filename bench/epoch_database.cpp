// Epoch database benchmark (reported, not asserted):
//  1. bytes of database per epoch for a 50-zone configuration (50 zones x 4 quantities,
//     registration with 6 targets, two per-core-point float32 arrays of 10,000 values),
//     and the time of one epoch commit (synchronous=FULL);
//  2. the series query for one zone and quantity over one year of 15-minute epochs
//     (35,040 epochs, generated), through the API and through `tlsmon query series`
//     end to end (target: under 100 ms); and `tlsmon status` on it (target: 15 ms).
// Every time is reported as its median and spread (quartiles and range), not only the best.
// Usage: bench_epoch_database [DIR [TLSMON]]  (DIR: where the databases go, kept for reruns;
// default a new temporary folder, removed at the end; TLSMON: the binary, default
// ../tlsmon, the build folder of this program).
#include "storage/epoch_database.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/utc_time.hpp"

namespace fs = std::filesystem;
using namespace tlsmon;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kZones = 50;
const char* const kQuantities[] = {"m3c2_mean_m", "m3c2_lod95_m", "keypoint_dx_m", "keypoint_dz_m"};
constexpr int kCorePoints = 10000;
constexpr UtcSeconds kStart = 1767225600;  // 2026-01-01T00:00:00Z
constexpr int kYearEpochs = 35040;         // 365 days x 96

double ms_since(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

std::string sha(std::int64_t n) {
    char buf[65];
    std::snprintf(buf, sizeof buf, "%064llx", static_cast<unsigned long long>(n));
    return buf;
}

std::string zone_name(int z) {
    return "zone " + std::to_string(z);
}

EpochResults epoch_results(int i, bool with_arrays) {
    EpochResults r;
    r.point_count = 2'000'000;
    r.timings = {1500.0, 400.0, 6000.0, 7900.0};
    RegistrationRow reg;
    reg.method = "targets-helmert";
    reg.transform = {1, 0, 0, 0.001, 0, 1, 0, -0.002, 0, 0, 1, 0.0005, 0, 0, 0, 1};
    reg.target_count = 6;
    reg.rms_m = 0.0011;
    reg.max_residual_m = 0.0019;
    reg.sigma0 = 1.02;
    reg.accepted = true;
    r.registration = reg;
    for (int t = 0; t < 6; ++t) {
        TargetObservation o;
        o.target = std::string("T").append(std::to_string(t));
        o.kind = t < 4 ? "sphere" : "plane";
        o.measured = {10.0 * t, 5.0, 2.0};
        o.residual = {0.0005, -0.0003, 0.0001};
        o.status = "found";
        o.use = "used";
        r.targets.push_back(o);
    }
    const double season = 0.004 * std::sin(2 * M_PI * i / 35040.0);
    for (int z = 0; z < kZones; ++z) {
        for (const char* q : kQuantities) {
            r.zone_results.push_back({zone_name(z), q, season + 0.0001 * z, 0.0018, 400 + z,
                                      std::fabs(season) > 0.0018});
        }
    }
    if (with_arrays) {
        std::vector<float> d(kCorePoints), lod(kCorePoints);
        for (int k = 0; k < kCorePoints; ++k) {
            d[k] = static_cast<float>(season + 0.001 * std::sin(0.37 * k + i));
            lod[k] = static_cast<float>(0.0015 + 0.0005 * std::cos(0.11 * k));
        }
        r.core_point_arrays = {{"m3c2_distance_m", d}, {"m3c2_lod95_m", lod}};
    }
    return r;
}

void fill(EpochDatabase& db, int epochs, bool with_arrays, std::vector<double>* commit_ms) {
    for (int z = 0; z < kZones; ++z) db.site().upsert_zone(zone_name(z), "{}");
    for (int i = 0; i < epochs; ++i) {
        const auto id = db.epochs()
                            .insert({sha(i + 1), kStart + 900LL * i, "/ingest/scan.ptx",
                                     180'000'000, std::nullopt})
                            .id;
        db.epochs().claim(id);
        const auto results = epoch_results(i, with_arrays);
        const auto t = Clock::now();
        db.results().commit(id, results);
        if (commit_ms) commit_ms->push_back(ms_since(t));
    }
}

// The value at fraction q (0..1) of the sorted sample, interpolated between neighbours.
double quantile(const std::vector<double>& sorted, double q) {
    const double at = q * static_cast<double>(sorted.size() - 1);
    const auto below = static_cast<std::size_t>(at);
    const std::size_t above = std::min(below + 1, sorted.size() - 1);
    return sorted[below] + (at - static_cast<double>(below)) * (sorted[above] - sorted[below]);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return quantile(v, 0.5);
}

// "median 1.23 ms (quartiles 1.10-1.40, range 1.02-2.50, n=11)".
std::string spread(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    char buf[160];
    std::snprintf(buf, sizeof buf, "median %.2f ms (quartiles %.2f-%.2f, range %.2f-%.2f, n=%zu)",
                  quantile(v, 0.5), quantile(v, 0.25), quantile(v, 0.75), v.front(), v.back(),
                  v.size());
    return buf;
}

// The program started directly (no shell: a user's shell is already running, and `sh -c`
// would add its own start of about 3 ms), its output to /dev/null; the wall time until it
// exits.
double run_binary(const std::vector<std::string>& arguments) {
    std::vector<char*> argv;
    for (const auto& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    const auto t = Clock::now();
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    int status = 0;
    if (spawned != 0 || waitpid(pid, &status, 0) != pid)
        throw std::runtime_error("cannot run " + arguments.front());
    const double ms = ms_since(t);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw std::runtime_error("failed (" + std::to_string(status) + "): " + arguments.front() +
                                 " " + arguments.at(1));
    return ms;
}

// A new folder under the system's temporary folder (mkdtemp: a fresh unique name, never a
// fixed path another user could have prepared), removed with its contents at the end.
class ScratchFolder {
  public:
    ScratchFolder() {
        std::string name = (fs::temp_directory_path() / "tlsmon-bench-db-XXXXXX").string();
        if (!::mkdtemp(name.data())) throw std::runtime_error("mkdtemp failed for " + name);
        path_ = name;
    }
    // Ctrl-C or a timeout during the long year generation would leave a database of about a
    // gigabyte behind: SIGINT and SIGTERM go to a thread that removes the folder and ends the
    // program (called before any other thread starts, so every thread has them blocked).
    void remove_on_signal() const {
        sigset_t set;
        sigemptyset(&set);
        sigaddset(&set, SIGINT);
        sigaddset(&set, SIGTERM);
        pthread_sigmask(SIG_BLOCK, &set, nullptr);
        std::thread([set, dir = path_] {
            int sig = 0;
            sigwait(&set, &sig);
            std::error_code ec;
            fs::remove_all(dir, ec);
            std::_Exit(128 + sig);
        }).detach();
    }
    ~ScratchFolder() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    ScratchFolder(const ScratchFolder&) = delete;
    ScratchFolder& operator=(const ScratchFolder&) = delete;
    const fs::path& path() const { return path_; }

  private:
    fs::path path_;
};

void run(const fs::path& dir, const fs::path& tlsmon);

}  // namespace

int main(int argc, char** argv) {
    // Line by line, so a run stopped during the long year generation keeps what it measured.
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    try {
        const fs::path tlsmon =
            argc > 2 ? fs::path(argv[2])
                     : fs::read_symlink("/proc/self/exe").parent_path() / ".." / "tlsmon";
        if (argc > 1) {
            fs::create_directories(argv[1]);
            run(argv[1], tlsmon);
        } else {
            ScratchFolder scratch;
            scratch.remove_on_signal();
            run(scratch.path(), tlsmon);
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_epoch_database: %s\n", e.what());
        return 1;
    }
}

namespace {

void run(const fs::path& dir, const fs::path& tlsmon) {
    // 1. Bytes per epoch: N epochs, then closed (the WAL is checkpointed into the file).
    constexpr int kSizeEpochs = 200;
    for (bool arrays : {false, true}) {
        const fs::path path = dir / (arrays ? "size_arrays.sqlite" : "size_rows.sqlite");
        fs::remove(path);
        std::vector<double> commit_ms;
        std::int64_t empty_bytes = 0;
        {
            auto db = EpochDatabase::open(path, EpochDatabase::Mode::read_write);
            fill(db, 0, arrays, nullptr);
        }
        empty_bytes = static_cast<std::int64_t>(fs::file_size(path));
        {
            auto db = EpochDatabase::open(path, EpochDatabase::Mode::read_write);
            fill(db, kSizeEpochs, arrays, &commit_ms);
        }
        const auto bytes = static_cast<std::int64_t>(fs::file_size(path));
        std::printf(
            "bytes per epoch, %d zones x 4 quantities%s: %.0f B (%d epochs, file %lld B);"
            " epoch commit %s\n",
            kZones, arrays ? " + 2 x 10,000 float32 core point arrays" : "",
            double(bytes - empty_bytes) / kSizeEpochs, kSizeEpochs, static_cast<long long>(bytes),
            spread(commit_ms).c_str());
    }

    // 2. One year of 15-minute epochs, 50 zones x 4 quantities each (7,008,000 series rows);
    //    generated once and kept in DIR for reruns.
    const fs::path year = dir / "year.sqlite";
    if (!fs::exists(year)) {
        const auto t = Clock::now();
        auto db = EpochDatabase::open(year, EpochDatabase::Mode::read_write);
        fill(db, kYearEpochs, false, nullptr);
        std::printf("generated %d epochs in %.1f s\n", kYearEpochs, ms_since(t) / 1000);
    }
    std::printf("year database: %lld B\n", static_cast<long long>(fs::file_size(year)));
    auto db = EpochDatabase::open(year, EpochDatabase::Mode::read_only);
    std::vector<double> api_ms;
    std::size_t rows = 0;
    for (int k = 0; k < 12; ++k) {  // the first one cold, then 11
        const auto t = Clock::now();
        rows = db.series().points("zone 17", "m3c2_mean_m", {}).size();
        api_ms.push_back(ms_since(t));
    }
    std::printf(
        "series query (API), one zone over one year: %zu rows, first %.1f ms, then %s"
        " (target 100 ms: %.2fx)\n",
        rows, api_ms.front(), spread({api_ms.begin() + 1, api_ms.end()}).c_str(),
        median({api_ms.begin() + 1, api_ms.end()}) / 100.0);
    for (const char* format : {"table", "csv", "json"}) {
        std::vector<double> cli_ms;
        const std::vector<std::string> cmd = {
            tlsmon.string(), "query",   "series",     "--db",        year.string(),
            "--zone",        "zone 17", "--quantity", "m3c2_mean_m", "--format",
            format,          "--from",  "2026-01-01", "--to",        "2026-12-31T23:59:59Z"};
        for (int k = 0; k < 7; ++k) cli_ms.push_back(run_binary(cmd));
        std::printf("tlsmon query series --format %s, end to end: %s (target 100 ms: %.2fx)\n",
                    format, spread(cli_ms).c_str(), median(cli_ms) / 100.0);
    }
    std::vector<double> status_ms;
    const std::vector<std::string> status = {tlsmon.string(), "status", "--db", year.string()};
    for (int k = 0; k < 15; ++k) status_ms.push_back(run_binary(status));
    std::printf("tlsmon status, end to end: %s (target 15 ms: %.2fx)\n", spread(status_ms).c_str(),
                median(status_ms) / 15.0);
}

}  // namespace
