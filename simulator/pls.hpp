#pragma once
// A personal laser scanner's campaign (docs/campaigns.md, "Simulated campaigns"): an
// inspector walks a path through the site with a SLAM-based handheld scanner, which fires
// pulses in every direction as it goes; the cloud is unstructured, noisier than a TLS scan
// (1–3 cm) and deformed in itself by the SLAM's drift.
//
// Measurement model per pulse k at time t_k along the walk (sensor at s(t_k)):
//   direction       d uniform on the sphere, except the cone under the operator's feet
//   true point      q = s + r·d, r the range to the scene's surface (ray_cast.hpp)
//   measured range  r + N(0, σ_r²); no point beyond max_range, within min_range, or when the
//                   return ρ·|cos α| is below min_return
//   measured point  p = s + τ(t) + R(ω(t))·(s + r_m·d − s),
// i.e. the SLAM's pose error at t: its position off by τ(t) and its attitude turned by the
// rotation vector ω(t) about the sensor. Drift models: none; linear (τ and ω grow in
// proportion to the time walked, to given values at the end); a random walk (τ and ω
// integrate white noise of given spectral density, sampled at knots and linear between, so
// that the error is continuous and surfaces seen at different times carry different errors).
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "simulator/scene.hpp"

namespace tlsmon::sim {

struct PlsTrajectory {
    std::vector<Eigen::Vector3d> waypoints;  // the sensor's path, m, walked in order
    double speed = 1.0;                      // m/s, walking pace
};

enum class SlamDriftModel { none, linear, random_walk };
const char* drift_model_name(SlamDriftModel model);
// "none", "linear", "random-walk"; throws Error for another name.
SlamDriftModel drift_model(const std::string& name);

struct SlamDrift {
    SlamDriftModel model = SlamDriftModel::none;
    // Linear: the error at the end of the walk.
    Eigen::Vector3d end_translation{0.020, -0.015, 0.010};  // m
    Eigen::Vector3d end_rotation_mrad{0.3, -0.2, 0.5};      // mrad, about x, y, z
    // Random walk: per axis σ of the increment over one second.
    double translation_density = 0.003;   // m/√s
    double rotation_density_mrad = 0.04;  // mrad/√s
    double knot_seconds = 1.0;            // between the walk's sampled values
    std::uint64_t seed = 5;
};

struct PlsScanner {
    double pulse_rate = 30000.0;   // pulses per second (a handheld's ≈ 300 k; less for tests)
    double max_range = 50.0;       // m
    double min_range = 0.5;        // m, the operator and the scanner's own housing
    double range_sigma = 0.02;     // m, per point
    double min_return = 0.01;      // ρ·|cos α|, weaker returns give no point
    double blind_cone_deg = 25.0;  // about straight down: the operator's body
    std::uint64_t seed = 3;
};

struct PlsCampaign {
    PlsTrajectory trajectory;
    PlsScanner scanner;
    SlamDrift drift;
};

// The SLAM's pose error at one time: p_measured = s + τ + R(ω)·(p − s).
struct SlamPoseError {
    Eigen::Vector3d rotation = Eigen::Vector3d::Zero();     // ω, rad
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();  // τ, m
    Eigen::Vector3d apply(const Eigen::Vector3d& sensor, const Eigen::Vector3d& p) const;
};

// The drift over one walk of `duration` seconds, sampled once (a pure function of the seed).
class SlamDriftPath {
  public:
    SlamDriftPath(const SlamDrift& drift, double duration);
    SlamPoseError at(double t) const;

  private:
    SlamDrift drift_;
    double duration_;
    std::vector<SlamPoseError> knots_;  // random walk: at k·knot_seconds
};

// Total path length / speed, s.
double walk_duration(const PlsTrajectory& trajectory);
// The sensor's true position at time t (clamped to the walk).
Eigen::Vector3d sensor_position(const PlsTrajectory& trajectory, double t);

struct PlsCloud {
    std::vector<Eigen::Vector3d> points;  // measured (noise and drift)
    std::vector<Eigen::Vector3d> truth;   // the surface point each pulse hit, noise-free
    std::vector<Eigen::Vector3f> normal;  // the surface's outward unit normal there
    std::vector<float> time;              // s since the walk's start
    std::vector<float> intensity;         // 0–1
    std::vector<std::uint8_t> surface;    // Surface (ray_cast.hpp)
    double duration = 0;                  // s
};

// Renders the campaign through the site at `epoch` on `threads` threads (the result does not
// depend on the thread count).
PlsCloud render_pls(const Site& site, int epoch, const PlsCampaign& campaign, unsigned threads = 2);

// The cloud's points as measured without range noise: each true point through the SLAM's pose
// error at its (stored) time. What a segment's true transformation is fitted on.
std::vector<Eigen::Vector3d> noise_free_points(const PlsCampaign& campaign, const PlsCloud& cloud);

// A loop around the pier's foundation, under the deck, at 1.5 m above the ground: 8 m west of
// the pier, 4 m east, 6 m south and north (clear of the presets' walls and abutment).
PlsTrajectory walk_around_pier(const Site& site);

// The SLAM's own frame in the scene: its origin where the walk starts, its x axis where the
// scanner pointed then — `heading` (rad, counter-clockwise) from the first leg — levelled (the
// scanner's inertial unit finds the vertical): the frame a handheld scanner's cloud comes in
// before anyone georeferences it. x_scene = F·x_slam.
Eigen::Matrix4d slam_frame(const PlsTrajectory& trajectory, double heading);

// Throws Error naming the value that cannot give a campaign.
void validate(const PlsCampaign& campaign);

}  // namespace tlsmon::sim
