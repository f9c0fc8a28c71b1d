#pragma once
// An epoch database with archive and quarantine folders in a scratch folder, and small XYZ
// scans written by the tests: what the pipeline tests process, in-process, on real files and
// a real SQLite file.
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>

#include "pipeline/epoch_pipeline.hpp"
#include "pipeline/sha256.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon::test {

namespace fs = std::filesystem;

struct PipelineSite {
    TempDir dir;
    PipelineConfig config = make_config();
    std::optional<EpochDatabase> db = open();

    PipelineConfig make_config() {
        PipelineConfig c;
        c.archive = dir / "archive";
        c.quarantine = dir / "quarantine";
        fs::create_directories(c.archive);
        fs::create_directories(c.quarantine);
        fs::create_directories(dir / "ingest");
        c.coverage.min_inside_share = 0.5;
        return c;
    }
    EpochDatabase open() {
        return EpochDatabase::open(dir / "tlsmon.sqlite", EpochDatabase::Mode::read_write);
    }
    // A stop and a start: a new connection (and, at the call site, a new ReferenceCache).
    void restart() {
        db.reset();
        db.emplace(open());
    }

    // A 21 x 21 grid of points at 0.5 m spacing on the plane z = height, moved by `offset`,
    // as an XYZ file in the ingest folder; returns the new pending epoch (each call must give
    // other points: the same content is the same epoch).
    Epoch add_epoch(const std::string& name, UtcSeconds acquired, double height = 0.0,
                    const Eigen::Vector3d& offset = Eigen::Vector3d::Zero()) {
        std::ostringstream text;
        text.precision(12);  // millimetres at UTM-sized coordinates
        for (int i = 0; i <= 20; ++i) {
            for (int j = 0; j <= 20; ++j) {
                const Eigen::Vector3d p = Eigen::Vector3d(0.5 * i, 0.5 * j, height) + offset;
                text << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
            }
        }
        const fs::path file = write_file(dir / "ingest" / name, text.str());
        const EpochInsert ins = db->epochs().insert(
            NewEpoch{sha256_file(file), acquired, file,
                     static_cast<std::int64_t>(fs::file_size(file)), std::nullopt});
        EXPECT_TRUE(ins.inserted) << name << " has the content of an earlier epoch";
        return *db->epochs().find(ins.id);
    }

    EpochOutcome process(const Epoch& epoch, ReferenceCache& cache) {
        SystemEventLog events;
        PipelineContext ctx{*db, config, events, cache};
        return process_epoch(ctx, epoch);
    }
};

// M3C2 parameters for the plate of PipelineSite::add_epoch: core points on cubes of 2 m,
// normals of radius 1.5 m oriented up, cylinders of 1 m; no zones (the caller's).
inline M3c2Config plate_m3c2_config() {
    M3c2Config c;
    c.core_spacing = 2.0;
    c.normal_radii = {1.5};
    c.cylinder_radius = 1.0;
    c.max_depth = 0.5;
    c.min_points = 3;
    c.orient_to_scanner = false;
    c.orientation = Eigen::Vector3d::UnitZ();
    c.registration_error = 0.001;
    return c;
}

}  // namespace tlsmon::test
