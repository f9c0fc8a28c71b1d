// Acceptance (issue 9): orthoimage cross-correlation of two `pier` epochs recovers the true
// horizontal and vertical shift of the south face within 0.5 mm, with noise and drift off.
//
// The epochs: epoch 0 and the epoch of the first day whose south-face displacement within
// the face (x and z, what the orthoimage sees) differs most from epoch 0's, both read from
// the truth at run time (the bending's law is the truth's business, not this test's). The patches:
// 0.5 m squares of the south face centred on the truth's sample points there; the shift varies with
// height (u ∝ z² along x, ∝ z up), and over 0.5 m it is linear to 2 µm, so a patch's translation is
// the truth at its centre.
//
// To keep the test fast each epoch is rendered only around one patch at a time
// (narrow_window.hpp: the `pier` preset's angular step and geometry, a ±0.6° window).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "algorithms/image_correlation.hpp"
#include "algorithms/orthoimage.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "simulator/truth.hpp"
#include "tests/simulator/narrow_window.hpp"

namespace tlsmon::sim {
namespace {

Eigen::Vector3d vec(const nlohmann::json& j) {
    return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

double hours_of(const Site& s, int epoch) {
    return epoch * s.cadence_seconds / 3600.0;
}

// The epoch's air, sun and bending, at the series' default start (as `tlsmon simulate`).
EpochConditions conditions(const Site& s, int epoch) {
    return epoch_conditions(s, epoch, hours_of(s, epoch));
}

// The truth's south-face samples at an epoch: name -> (point, displacement).
struct Sample {
    std::string name;
    Eigen::Vector3d point, displacement;
};
std::vector<Sample> south_face(const Site& s, int epoch) {
    const EpochConditions c = conditions(s, epoch);
    const nlohmann::json truth = truth_json(s, epoch, c.hours, c.utc, nullptr);
    std::vector<Sample> out;
    for (const auto& j : truth.at("samples")) {
        const std::string name = j.at("name").get<std::string>();
        if (name.rfind("south_face", 0) != 0) continue;
        out.push_back({name, vec(j.at("point")), vec(j.at("displacement"))});
    }
    return out;
}

// Orthoimage of the south face (plane y = y0, u = x east, v = z up) over a square of half
// side `half` about (x, z): 4 mm pixels, σ_s 12 mm, about the point spacing (10–16 mm on
// this face at 0.013°), so the kernel's response at the sampling frequency is e^(−2π²) and
// the lattice leaves no pattern of its own in the image. What aliasing remains is in the
// samples: the beam's σ (w/2, 3.5–5 mm here) is a third of the spacing, so the 2 cm
// formwork joints, the strongest features, are still under-sampled: up to ≈ 0.3 mm of
// error on patches that hold a joint for shifts of 5–11 mm, against ≤ 0.03 mm with the
// joints taken out or with the angular step halved (0.0065°).
constexpr double kPixel = 0.004, kSigma = 0.012;
Orthoimage face_image(const Site& s, const Scan& scan, const Eigen::Vector2d& centre, double half) {
    OrthoPlane plane;
    plane.origin = {0.0, s.pier.y0, 0.0};
    plane.u = Eigen::Vector3d::UnitX();
    plane.v = Eigen::Vector3d::UnitZ();
    plane.max_distance = 0.1;  // well beyond the face's bending towards the scanner
    OrthoGrid grid;
    grid.pixel_size = kPixel;
    grid.kernel_sigma = kSigma;
    const auto n = static_cast<Eigen::Index>(std::lround(2.0 * half / kPixel)) + 1;
    grid.rows = grid.columns = n;
    grid.first_centre = centre - Eigen::Vector2d::Constant(half);
    return rasterise_orthoimage(scan.xyz, scan.intensity, plane, grid);
}

// The epoch's scan with the atmosphere's range scale taken out (as the pipeline will, from
// the meteo file; here from the truth): r ← r / (n_true / n_setting) about the scanner,
// whose pose is exact with drift off. Otherwise a few ppm of range between two epochs'
// air would move the face by ≈ 0.1 mm along the line of sight, in-plane in part.
Scan measured_scan(const Site& w, int epoch) {
    const EpochConditions c = conditions(w, epoch);
    Scan scan = render_epoch(w, c, 2).scan;
    const double scale = c.atmosphere.range_scale;
    const Eigen::Vector3d o = w.scanner.position;
    for (Eigen::Vector3d& p : scan.xyz) p = o + (p - o) / scale;
    return scan;
}

TEST(SimulatorAcceptance, OrthoimageCorrelationRecoversTheSouthFaceShift) {
    Site s = preset_pier();
    s.noise.enabled = false;
    s.drift.enabled = false;

    // The epoch of the first day that moved the south face most within its plane.
    const std::vector<Sample> first = south_face(s, 0);
    const int day = static_cast<int>(std::lround(86400.0 / s.cadence_seconds));
    int epoch = 0;
    double largest = 0.0;
    for (int e = 1; e <= day; ++e) {
        const std::vector<Sample> now = south_face(s, e);
        for (std::size_t i = 0; i < now.size(); ++i) {
            const Eigen::Vector3d dd = now[i].displacement - first[i].displacement;
            const double d = std::hypot(dd.x(), dd.z());
            if (d > largest) {
                largest = d;
                epoch = e;
            }
        }
    }
    ASSERT_GT(largest, 0.002) << "the truth shows no substantial displacement in a day";
    const std::vector<Sample> later = south_face(s, epoch);
    std::printf(
        "epochs 0 and %d (%.2f h): largest in-plane south-face displacement %.1f mm, "
        "atmosphere %.2f and %.2f ppm\n",
        epoch, hours_of(s, epoch), 1e3 * largest, conditions(s, 0).atmosphere.ppm,
        conditions(s, epoch).atmosphere.ppm);

    constexpr double half = 0.25;      // template: 0.5 m square
    constexpr int search_radius = 12;  // ±48 mm
    const double margin = (search_radius + 3) * kPixel;
    std::size_t measured = 0;
    for (std::size_t i = 0; i < first.size(); ++i) {
        const Eigen::Vector3d& p = first[i].point;
        Site w = s;
        test::narrow_window(w.scanner, p, 0.6);
        const Scan scan0 = measured_scan(w, 0);
        const Scan scan1 = measured_scan(w, epoch);
        const Eigen::Vector2d centre(p.x(), p.z());
        const Orthoimage templ = face_image(s, scan0, centre, half);
        const Orthoimage search = face_image(s, scan1, centre, half + margin);
        ASSERT_GT(templ.image.valid.count(), 0.98 * templ.image.valid.size()) << first[i].name;

        CorrelationParameters cp;
        cp.search_radius = search_radius;
        const int o = static_cast<int>(std::lround(margin / kPixel));
        const CorrelationResult r = correlate_template(templ.image, search.image, {o, o}, cp);
        ASSERT_TRUE(r.found) << first[i].name;
        // Movement of the material point between the epochs, in the face's (x, z).
        const Eigen::Vector3d d = later[i].displacement - first[i].displacement;
        const Eigen::Vector2d truth(d.x(), d.z());
        const Eigen::Vector2d error = kPixel * r.shift - truth;
        std::printf(
            "%-16s truth (%7.3f, %6.3f) mm  error (%6.3f, %6.3f) mm  σ (%.3f, %.3f) mm  "
            "NCC %.4f\n",
            first[i].name.c_str(), 1e3 * truth.x(), 1e3 * truth.y(), 1e3 * error.x(),
            1e3 * error.y(), 1e3 * kPixel * std::sqrt(r.covariance(0, 0)),
            1e3 * kPixel * std::sqrt(r.covariance(1, 1)), r.ncc);
        EXPECT_LT(std::abs(error.x()), 0.0005) << first[i].name << " horizontal";
        EXPECT_LT(std::abs(error.y()), 0.0005) << first[i].name << " vertical";
        ++measured;
    }
    EXPECT_GE(measured, 4u);
}

}  // namespace
}  // namespace tlsmon::sim
