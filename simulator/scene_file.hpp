#pragma once
// Reading a simulator scene file (TOML, see etc/simulator-small.toml) into sim::Site.
// The file starts from a preset (`preset = "small"` or the caller's choice) and overrides
// any parameter; unknown keys and out-of-range values are ConfigErrors naming the key and
// its line.
#include <filesystem>
#include <optional>
#include <string>

#include "core/toml_fields.hpp"
#include "simulator/scene.hpp"

namespace tlsmon {

// `preset`: the caller's choice (command line), or nullopt to use the file's `preset` key
// (default "small"). A file naming a different preset than the caller is an error.
sim::Site load_scene_file(const std::filesystem::path& path,
                          const std::optional<std::string>& preset);
sim::Site parse_scene_file(std::string_view text, const std::string& source_name,
                           const std::optional<std::string>& preset);

}  // namespace tlsmon
