// Writing an 8-bit RGB image as a PNG file with libpng (its simplified
// png_image API), as an output of a run (core/outputs.h). Only png_image.cpp
// includes png.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

#include "core/outputs.h"

namespace rayverify {

// `rgb` holds width × height pixels, row by row from the top, 3 bytes each,
// encoded into `file` (which appears with the run's other outputs, or not at
// all). Throws input_error when the image is malformed or cannot be written.
void write_png(output_file& file, int width, int height, std::span<const std::uint8_t> rgb);

}  // namespace rayverify
