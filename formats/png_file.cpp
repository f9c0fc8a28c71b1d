#include "formats/png_file.hpp"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <string>

#include "core/error.hpp"

namespace tlsmon {

namespace {

// libpng reports errors by longjmp to the setjmp in write_png_rgb; the message is kept.
void on_error(png_structp png, png_const_charp message) {
    auto* what = static_cast<std::string*>(png_get_error_ptr(png));
    *what = message;
    std::longjmp(png_jmpbuf(png), 1);
}

void on_warning(png_structp, png_const_charp) {}

}  // namespace

void write_png_rgb(const std::filesystem::path& path, int rows, int columns,
                   const std::vector<std::uint8_t>& rgb) {
    if (rows <= 0 || columns <= 0 ||
        rgb.size() != static_cast<std::size_t>(rows) * static_cast<std::size_t>(columns) * 3) {
        throw Error(path.string() + ": cannot write the picture: " + std::to_string(rows) + " x " +
                    std::to_string(columns) + " pixels do not match " + std::to_string(rgb.size()) +
                    " bytes");
    }
    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (!file) throw Error(path.string() + ": cannot write the picture: " + std::strerror(errno));
    std::string what;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &what, on_error, on_warning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info) {
        png_destroy_write_struct(&png, nullptr);
        std::fclose(file);
        throw Error(path.string() + ": cannot write the picture: out of memory");
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        std::fclose(file);
        throw Error(path.string() + ": cannot write the picture: " + what);
    }
    png_init_io(png, file);
    png_set_IHDR(png, info, static_cast<png_uint_32>(columns), static_cast<png_uint_32>(rows), 8,
                 PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    const std::size_t stride = static_cast<std::size_t>(columns) * 3;
    for (int r = 0; r < rows; ++r)
        png_write_row(png, rgb.data() + static_cast<std::size_t>(r) * stride);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    const bool failed = std::ferror(file) != 0;
    if (std::fclose(file) != 0 || failed)
        throw Error(path.string() + ": write failed: " + std::strerror(errno));
}

}  // namespace tlsmon
