#pragma once
// The site configuration `tlsmon simulate` writes beside its scans: the station's name, its
// reference targets with approximate positions (to the centimetre, as a site sketch gives
// them) and zones around the pier's faces (a round pier: one zone holding its cylinder), as
// [station], [[target]] and [[zone]] tables of a tlsmon configuration (docs/configuration.md). A
// valid configuration on its own (every other key at its default), so `tlsmon register --config
// site.toml` and the tests need nothing written by hand.
#include <string>

#include "simulator/scene.hpp"

namespace tlsmon {

std::string site_configuration(const sim::Site& site);

// A no-change check zone ([[zone]] with no_change = true, docs/calibration.md) on the face of
// the site's first abutment that never moves, the face the scanner sees most squarely,
// 0.6 m in from its edges (so that no M3C2 cylinder reaches the ground or the top) and
// 0.3 m either side of it; "" when the site has no such abutment.
std::string abutment_check_zone(const sim::Site& site);

}  // namespace tlsmon
