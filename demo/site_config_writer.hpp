#pragma once
// The site configuration `tlsmon simulate` writes beside its scans: the station's name, its
// reference targets with approximate positions (to the centimetre, as a site sketch gives
// them) and zones around the pier's faces, as [station], [[target]] and [[zone]] tables of a
// tlsmon configuration (docs/configuration.md). A valid configuration on its own (every other
// key at its default), so `tlsmon register --config site.toml` and the tests need nothing
// written by hand.
#include <string>

#include "simulator/scene.hpp"

namespace tlsmon {

std::string site_configuration(const sim::Site& site);

}  // namespace tlsmon
