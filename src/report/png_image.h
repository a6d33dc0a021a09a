// Writing an 8-bit RGB image as a PNG file with libpng (its simplified
// png_image API), atomically. Only png_image.cpp includes png.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

namespace rayverify {

// `rgb` holds width × height pixels, row by row from the top, 3 bytes each.
// The file appears whole or not at all; throws input_error when the image is
// malformed or the file cannot be written.
void write_png(const std::filesystem::path& file, int width, int height, std::span<const std::uint8_t> rgb);

}  // namespace rayverify
