#include "cli/file_pair.hpp"

#include <filesystem>

#include "config/keys.hpp"
#include "core/error.hpp"
#include "daemon/ingest_files.hpp"
#include "formats/meteo_csv.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/epoch_meteo.hpp"
#include "pipeline/registration_stage.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

Epoch epoch_of(EpochId id, const std::string& file, const std::optional<Config>& site) {
    Epoch e;
    e.id = id;
    e.file_path = file;
    std::string used;
    if (site) e.acquired = acquisition_time(file, site->ingest.acquisition_time, used);
    return e;
}

// The sidecar beside the file, as the daemon would use it (none when absent or rejected).
std::optional<MeteoSidecar> meteo_of(const Epoch& e, const Config& site) {
    const fs::path sidecar = meteo_sidecar_of(e.file_path);
    std::error_code ec;
    if (!fs::is_regular_file(sidecar, ec)) return std::nullopt;
    auto meteo = read_epoch_meteo(sidecar, e, site.meteo);
    if (!meteo || meteo->outcome != MeteoOutcome::used) return std::nullopt;
    return meteo;
}

// What the daemon knew of the targets when this epoch arrived (the site's database, when it
// has one): those excluded as moved by an epoch acquired before it and not re-surveyed, and
// their runs of failed outlier tests just before it.
void targets_before(const Epoch& e, const Config& site, StageHistory& history) {
    std::error_code ec;
    if (!fs::is_regular_file(site.paths.database, ec)) return;
    const auto db = EpochDatabase::open(site.paths.database, EpochDatabase::Mode::read_only);
    for (const auto& x : db.registrations().exclusions()) {
        if (x.excluded_acquired < e.acquired && !x.resurveyed)
            history.excluded_targets.insert(x.target);
    }
    history.outlier_runs = db.registrations().outlier_runs(e.acquired, kMaxConfirmExclusionEpochs);
}

}  // namespace

FilePair read_files(const std::string& reference, const std::string& epoch,
                    const std::optional<Config>& site) {
    FilePair pair;
    pair.reference = epoch_of(1, reference, site);
    pair.epoch = epoch_of(2, epoch, site);
    pair.reference_scans = std::make_shared<const std::vector<Scan>>(read_scans(reference));
    pair.epoch_scans = std::make_shared<const std::vector<Scan>>(read_scans(epoch));
    return pair;
}

FilePair read_file_pair(const std::string& reference, const std::string& epoch,
                        const std::optional<Config>& site) {
    FilePair pair = read_files(reference, epoch, site);
    if (!site) {
        pair.registration = "none: the files are taken as in one frame";
        return pair;
    }
    if (!can_register(pipeline_config(*site).registration)) {
        pair.registration = "none: the site configures no registration";
        return pair;
    }
    RegistrationResult result;
    const StageVerdict verdict = register_file_pair(pair, *site, result);
    if (!verdict.ran()) {
        throw Error("registration of " + epoch + " onto " + reference + ": " + verdict.rejected +
                    " (the daemon stores this epoch rejected, without analyses)");
    }
    pair.outputs = RegistrationStage::outputs_of(
        result, EpochInput{pair.epoch, pair.epoch_scans, std::nullopt});
    pair.registration = verdict.note;
    return pair;
}

StageVerdict register_file_pair(const FilePair& pair, const Config& site,
                                RegistrationResult& result) {
    const PipelineConfig pipeline = pipeline_config(site);
    ReferenceEpoch reference(pair.reference, [scans = pair.reference_scans] { return scans; });
    ReferenceCache cache;  // in memory: this run's products only
    StageHistory history;
    targets_before(pair.epoch, site, history);
    history.reference_meteo = meteo_of(pair.reference, site);
    const EpochInput input{pair.epoch, pair.epoch_scans, meteo_of(pair.epoch, site)};
    StageOutputs outputs;
    EpochResults results;
    StageContext ctx{input, reference, cache, history, pipeline.zones, outputs, results};
    return RegistrationStage(pipeline.registration).measure(ctx, result);
}

std::optional<Config> site_config(const std::string& path) {
    if (path.empty()) return std::nullopt;
    return load_config(path);
}

std::string effective_parameters(const Config& config, const std::string& section) {
    std::string out;
    for (const auto& k : config_keys())
        if (k.section == section) out += section + "." + k.name + " = " + k.value(config) + "\n";
    return out;
}

std::vector<ZoneShape> whole_of(const std::vector<Scan>& scans) {
    Eigen::AlignedBox3d box;
    for (const auto& s : scans)
        for (const auto& p : s.xyz)
            if (p.allFinite()) box.extend(p);
    if (box.isEmpty()) throw Error("the reference holds no point");
    const Eigen::Vector3d margin = Eigen::Vector3d::Constant(1e-3);
    return {box_zone("all", box.min() - margin, box.max() + margin)};
}

void apply_segmentation_options(StableAreaConfig& segmentation, std::optional<double> voxel,
                                std::optional<double> seed) {
    if (voxel) segmentation.voxel = *voxel;
    if (seed) segmentation.seed = *seed;
    if (!(segmentation.voxel > 0) || !(segmentation.seed > segmentation.voxel))
        throw Error("--voxel and --seed: the supervoxels' size must exceed the voxel's (> 0)");
}

}  // namespace tlsmon
