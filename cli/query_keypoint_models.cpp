// `tlsmon query keypoint-models`: the keypoint displacement model d(t, z) refitted at each
// epoch (docs/keypoints.md, step 7; docs/schema.md, "keypoint_models"), read-only. One row per
// fit with its coefficients in the scaled variables u, w; with --residuals one row per
// residual of the fitting epoch's own segments instead.
#include <iostream>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

namespace {

Table models_table(const std::vector<StoredKeypointModel>& models) {
    Table t{{"epoch",
             "acquired",
             "quantity",
             "variable",
             "defined",
             "observations",
             "iterations",
             "converged",
             "t_centre",
             "t_scale",
             "z_centre",
             "z_scale",
             "a00",
             "a10",
             "a01",
             "a20",
             "a11",
             "a02",
             "a30",
             "a21",
             "a12",
             "a03",
             "sum_abs_residuals",
             "residual_scale",
             "reason"},
            {}};
    for (const auto& s : models) {
        const auto& m = s.model;
        std::vector<Cell> row{s.epoch,
                              format_utc(s.acquired),
                              m.quantity,
                              m.variable,
                              m.defined,
                              m.observations,
                              m.iterations,
                              m.converged,
                              optional_cell(m.t_centre),
                              optional_cell(m.t_scale),
                              optional_cell(m.z_centre),
                              optional_cell(m.z_scale)};
        for (int k = 0; k < 10; ++k)
            row.push_back(optional_cell(m.coefficients ? std::optional<double>((*m.coefficients)[k])
                                                       : std::nullopt));
        row.push_back(optional_cell(m.sum_abs_residuals));
        row.push_back(optional_cell(m.residual_scale));
        row.push_back(m.reason);
        t.rows.push_back(std::move(row));
    }
    return t;
}

Table residuals_table(const std::vector<StoredKeypointModel>& models) {
    Table t{{"epoch", "acquired", "quantity", "zone", "t", "z", "d", "residual"}, {}};
    for (const auto& s : models)
        for (const auto& r : s.model.residuals)
            t.rows.push_back({s.epoch, format_utc(s.acquired), s.model.quantity, r.zone, r.t, r.z,
                              r.d, r.residual});
    return t;
}

}  // namespace

int run_query_keypoint_models(const KeypointModelsOptions& options) {
    return run_reporting_errors("query keypoint-models", [&] {
        const auto range = time_range(options.read);
        const auto db = open_for_reading(options.read);
        const auto models = db.keypoint_models().in_range(
            range,
            options.quantity.empty() ? std::nullopt : std::optional<std::string>(options.quantity));
        print(std::cout, options.residuals ? residuals_table(models) : models_table(models),
              options.read.format);
    });
}

}  // namespace tlsmon
