#pragma once
// The two files of a one-shot comparison (`tlsmon m3c2`, `tlsmon keypoints`) as the daemon
// sees two epochs: read, and with a site configuration (--config) also timed, with their
// meteo sidecars, and the second registered onto the first by the site's registration stage
// (pipeline/registration_stage.hpp), leaving out the targets the site's database (when there
// is one) had excluded as moved before the epoch was acquired. So the command measures what
// the daemon stored for that epoch. Without a configuration the files are taken as already in
// one frame.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "pipeline/stage.hpp"

namespace tlsmon {

struct FilePair {
    Epoch reference, epoch;  // ids 1 and 2, their files and acquisition times
    std::shared_ptr<const std::vector<Scan>> reference_scans, epoch_scans;
    StageOutputs outputs;      // the epoch's map into the reference frame
    std::string registration;  // what the registration did, in a few words
};

// The files read, with their acquisition times by the site's ingest.acquisition_time.
FilePair read_files(const std::string& reference, const std::string& epoch,
                    const std::optional<Config>& site);

// read_files, then the registration. Throws Error naming the file, or the registration's reason
// when the site's registration rejects the epoch (the daemon stores it `rejected`, with no
// analysis).
FilePair read_file_pair(const std::string& reference, const std::string& epoch,
                        const std::optional<Config>& site);

// The site's registration stage measuring the pair (`tlsmon register`): its verdict, the
// result into `result`. Requires a site that can register.
StageVerdict register_file_pair(const FilePair& pair, const Config& site,
                                RegistrationResult& result);

// Without a site's zones: one zone "all" around every point of `scans` (the patch commands'
// whole-file comparison). Throws Error when they hold no point.
std::vector<ZoneShape> whole_of(const std::vector<Scan>& scans);

// --voxel and --seed of the patch commands replace the segmentation's ([registration]
// stable_voxel, stable_seed). Throws Error unless the supervoxels exceed the voxel (> 0).
void apply_segmentation_options(StableAreaConfig& segmentation, std::optional<double> voxel,
                                std::optional<double> seed);

// The site's configuration from --config; none without.
std::optional<Config> site_config(const std::string& path);

// The configuration's section as the command uses it: `section = value` lines of every key
// of it (the daemon's `check-config` prints the same), so a user sees which method ran.
std::string effective_parameters(const Config& config, const std::string& section);

}  // namespace tlsmon
