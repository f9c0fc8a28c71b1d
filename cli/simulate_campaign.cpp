// `tlsmon simulate --campaign DRIFT`: a personal laser scanner's campaign walked around the
// scene's pier (simulator/pls.hpp) instead of the station's scans, for `tlsmon campaign
// compare`: campaign.ply (every point with its time, intensity, the surface its pulse hit and
// its true position), reference.ply (a drift-free survey of all sides at TLS noise, 2 mm) and
// campaign.truth.json (the walk, the drift model, the SLAM's pose error every second, and the
// frame the campaign is written in: the scene's, or with --slam-frame the SLAM's own).
#include <Eigen/LU>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "cli/commands.hpp"
#include "cli/result_file.hpp"
#include "core/error.hpp"
#include "formats/ply_writer.hpp"
#include "simulator/pls.hpp"
#include "simulator/scene_file.hpp"

namespace tlsmon {

namespace {

nlohmann::json vector_json(const Eigen::Vector3d& v) {
    return {v.x(), v.y(), v.z()};
}

void write_cloud(const std::filesystem::path& path, const sim::PlsCloud& cloud) {
    const std::size_t n = cloud.points.size();
    std::vector<float> tx(n), ty(n), tz(n);
    for (std::size_t i = 0; i < n; ++i) {
        tx[i] = float(cloud.truth[i].x());
        ty[i] = float(cloud.truth[i].y());
        tz[i] = float(cloud.truth[i].z());
    }
    const PlyAttribute attributes[] = {{"time", std::span<const float>(cloud.time)},
                                       {"intensity", std::span<const float>(cloud.intensity)},
                                       {"surface", std::span<const std::uint8_t>(cloud.surface)},
                                       {"true_x", std::span<const float>(tx)},
                                       {"true_y", std::span<const float>(ty)},
                                       {"true_z", std::span<const float>(tz)}};
    write_ply(path, cloud.points, attributes);
}

}  // namespace

void simulate_campaign(const sim::Site& site, const SimulateOptions& o) {
    sim::PlsCampaign campaign;
    campaign.trajectory = sim::walk_around_pier(site);
    campaign.drift.model = sim::drift_model(o.campaign);
    if (o.seed) campaign.scanner.seed = campaign.drift.seed = std::uint64_t(*o.seed);
    if (o.pulse_rate) campaign.scanner.pulse_rate = *o.pulse_rate;
    if (o.range_sigma) campaign.scanner.range_sigma = *o.range_sigma;
    sim::validate(campaign);
    const std::filesystem::path out(o.out);
    std::filesystem::create_directories(out);

    sim::PlsCampaign survey = campaign;
    survey.drift.model = sim::SlamDriftModel::none;
    survey.scanner.range_sigma = 0.002;
    survey.scanner.pulse_rate = 2 * campaign.scanner.pulse_rate;
    survey.scanner.seed = campaign.scanner.seed + 1000003;
    const sim::PlsCloud reference = sim::render_pls(site, 0, survey, o.threads);
    write_cloud(out / "reference.ply", reference);
    sim::PlsCloud cloud = sim::render_pls(site, 0, campaign, o.threads);
    // In the SLAM's frame the heading is wherever the scanner pointed at the start: drawn from
    // the seed (its fractional golden-ratio multiple, spread evenly over the circle).
    const double heading =
        2.0 * std::numbers::pi * std::fmod(0.6180339887 * double(campaign.drift.seed), 1.0);
    const Eigen::Matrix4d frame =
        o.slam_frame ? sim::slam_frame(campaign.trajectory, heading) : Eigen::Matrix4d::Identity();
    const Eigen::Matrix4d to_frame = frame.inverse();
    for (auto& p : cloud.points) p = (to_frame * p.homogeneous()).head<3>();
    write_cloud(out / "campaign.ply", cloud);

    nlohmann::json truth;
    for (const auto& w : campaign.trajectory.waypoints) truth["walk"].push_back(vector_json(w));
    truth["speed_m_s"] = campaign.trajectory.speed;
    truth["duration_s"] = cloud.duration;
    truth["range_sigma_m"] = campaign.scanner.range_sigma;
    truth["pulse_rate_hz"] = campaign.scanner.pulse_rate;
    truth["drift"] = {{"model", sim::drift_model_name(campaign.drift.model)},
                      {"seed", campaign.drift.seed}};
    // x_scene = F·x_campaign (identity unless --slam-frame); true_x/y/z are in the scene's frame.
    for (int r = 0; r < 4; ++r)
        truth["frame"].push_back({frame(r, 0), frame(r, 1), frame(r, 2), frame(r, 3)});
    // p = s + τ(t) + R(ω(t))·(q − s), s the sensor at t (docs/campaigns.md).
    const sim::SlamDriftPath drift(campaign.drift, cloud.duration);
    for (double t = 0; t <= cloud.duration + 1e-9; t += 1.0) {
        const sim::SlamPoseError e = drift.at(t);
        truth["pose_error"].push_back(
            {{"t_s", t},
             {"sensor", vector_json(sim::sensor_position(campaign.trajectory, t))},
             {"translation_m", vector_json(e.translation)},
             {"rotation_rad", vector_json(e.rotation)}});
    }
    ResultFile file((out / "campaign.truth.json").string());
    file.write(truth.dump(2) + "\n");
    file.close();
    std::cout << "campaign (" << sim::drift_model_name(campaign.drift.model)
              << " drift): " << (out / "campaign.ply").string() << " " << cloud.points.size()
              << " points over a " << cloud.duration
              << " s walk; reference: " << (out / "reference.ply").string() << " "
              << reference.points.size() << " points" << std::endl;
}

}  // namespace tlsmon
