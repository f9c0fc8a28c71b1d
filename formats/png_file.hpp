#pragma once
// PNG pictures for people (the keypoint matches drawn on the intensity images), written
// through libpng: 8-bit RGB, no interlacing.
#include <cstdint>
#include <filesystem>
#include <vector>

namespace tlsmon {

// `rgb`: rows × columns pixels, row by row, red, green, blue. Throws Error naming the file
// when it cannot be written.
void write_png_rgb(const std::filesystem::path& path, int rows, int columns,
                   const std::vector<std::uint8_t>& rgb);

}  // namespace tlsmon
