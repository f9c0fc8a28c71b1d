#pragma once
// A stored keypoint series with a known displacement model: five vertical-angle bands at
// heights 2, 6, 10, 14, 18 m, the reference epoch at `reference` and twelve epochs 15 min
// apart after it, each band displaced along the surface by
//   d(t, z) = 0.4 mm/h · t + 0.01 mm/(h m) · t z     (t in hours since the reference),
// and the last epoch's commit holding the model d(t, z) refitted over all of them, as the
// keypoint stage fits it (over the stored series plus the epoch's own segments).
#include <gtest/gtest.h>

#include <numbers>
#include <string>
#include <vector>

#include "pipeline/keypoint_results.hpp"
#include "storage/epoch_database.hpp"
#include "tests/storage/fake_sha256.hpp"

namespace tlsmon::test {

inline double band_displacement(double t_hours, double z) {
    return 0.4e-3 * t_hours + 0.01e-3 * t_hours * z;
}

struct KeypointBandSeries {
    std::vector<std::string> zones;  // by height
    EpochId last = 0;                // the epoch whose commit holds the model
    std::size_t stored_inputs = 0;   // observations read back from the stored series
};

inline KeypointBandSeries commit_keypoint_band_series(EpochDatabase& db, UtcSeconds reference) {
    KeypointBandSeries out;
    for (int b = 0; b < 5; ++b) {
        out.zones.push_back(keypoint_band_zone(18 + b, 5 * std::numbers::pi / 180));
        db.site().upsert_zone(out.zones.back(),
                              keypoint_band_zone_definition(18 + b, 5 * std::numbers::pi / 180));
    }
    const auto claimed = [&](int e) {
        const auto id =
            db.epochs()
                .insert({fake_sha256(e + 1), reference + 900 * e, "/i/s.ptx", 10, std::nullopt})
                .id;
        EXPECT_TRUE(db.epochs().claim(id));
        return id;
    };
    db.epochs().set_reference(claimed(0));
    db.results().commit(*db.epochs().reference(), EpochResults{});
    for (int e = 1; e <= 12; ++e) {
        const EpochId id = claimed(e);
        EpochResults r;
        std::vector<KeypointModelInput> inputs;
        if (e == 12) {
            inputs = stored_model_inputs(db.series(), out.zones, kKeypointAlongSurfaceH, reference);
            out.stored_inputs = inputs.size();
        }
        for (int b = 0; b < 5; ++b) {
            const double t = 0.25 * e, z = 2.0 + 4.0 * b;
            r.zone_results.push_back(
                {out.zones[b], kKeypointAlongSurfaceH, band_displacement(t, z), 0.0005, 40, true});
            r.zone_results.push_back({out.zones[b], kKeypointHeight, z, std::nullopt, 40, false});
            if (e == 12) inputs.push_back({out.zones[b], id, {t, z, band_displacement(t, z)}});
        }
        if (e == 12) {
            std::vector<keypoints::ModelObservation> obs;
            for (const auto& in : inputs) obs.push_back(in.observation);
            const auto model = keypoints::fit_displacement_model(obs);
            EXPECT_TRUE(model.defined()) << model.undefined_reason;
            r.keypoint_models = {
                keypoint_model_row(kKeypointAlongSurfaceH, "time_h", model, inputs, id)};
            out.last = id;
        }
        db.results().commit(id, r);
    }
    return out;
}

}  // namespace tlsmon::test
