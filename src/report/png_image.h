// Writing an 8-bit RGB image as PNG with libpng, row by row: memory is one
// row whatever the image's height. Only png_image.cpp includes png.h.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <span>
#include <string>

#include "core/outputs.h"

namespace rayverify {

// Encodes width × height pixels, given a row at a time from the top (3 bytes
// a pixel), into `out`. `name` names the file in errors. Throws input_error
// when a row has the wrong size, rows are missing or extra, or `out` fails.
class png_writer {
public:
    png_writer(std::ostream& out, std::string name, int width, int height);
    ~png_writer();
    png_writer(const png_writer&) = delete;
    png_writer& operator=(const png_writer&) = delete;

    void write_row(std::span<const std::uint8_t> rgb);
    // After the last row: the image's end, and the stream flushed.
    void finish();

private:
    struct encoder;
    std::unique_ptr<encoder> encoder_;
};

}  // namespace rayverify
