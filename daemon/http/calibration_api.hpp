#pragma once
// `/api/v1/calibration?from&to` (docs/http.md): whether the σ behind the site's alarms held
// up over a window — the table of `tlsmon calibration` without a truth (a real site has
// none): the check zones against zero, the used targets against each other, the agreement of
// joined registration estimates (report/calibration.hpp, docs/calibration.md).
#include "daemon/http/dashboard_api.hpp"

namespace tlsmon {

// Over the epochs acquired in `window` (open: every epoch).
Json calibration_json(const EpochDatabase& db, const TimeRange& window);

}  // namespace tlsmon
