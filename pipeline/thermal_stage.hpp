#pragma once
// Stage "thermal": each zone quantity named in [thermal] is compensated for the structure's
// thermal response (docs/thermal.md). It runs last, on what the other stages wrote:
//   - no model yet and the series a training window long (or the model due for a refresh):
//     fit one (algorithms/thermal/thermal_model.hpp) on the window's epochs — registered,
//     accepted, outside the zone's alarms — with the air temperatures of their meteo; stored
//     as the zone quantity's next version in this epoch's commit;
//   - with a model and the air of the lags' memory: the thermal prediction and the residual
//     (measured − predicted) with its σ, as zone quantities; the model health of the trailing
//     window as two more;
//   - every epoch: how it was compensated (thermal_compensations), and an event when that
//     quality or the model's health changes.
// It never rejects an epoch: without meteo or model the quantity is stored uncompensated and
// the epoch says so. A one-shot command (no stored history) does not compensate.
#include "pipeline/stage.hpp"
#include "pipeline/thermal_config.hpp"

namespace tlsmon {

class ThermalStage : public Stage {
  public:
    explicit ThermalStage(ThermalConfig config) : config_(std::move(config)) {}
    const char* name() const override { return "thermal"; }
    StageVerdict run(StageContext& ctx) const override;

  private:
    ThermalConfig config_;
};

}  // namespace tlsmon
