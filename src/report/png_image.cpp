#include "report/png_image.h"

#include <png.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "core/input_error.h"

namespace rayverify {

void write_png(output_file& file, int width, int height, std::span<const std::uint8_t> rgb) {
    if (width <= 0 || height <= 0 ||
        rgb.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3)
        throw input_error(file.path().string(), 0, "", "image size does not match its pixel buffer");

    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = static_cast<png_uint_32>(width);
    image.height = static_cast<png_uint_32>(height);
    image.format = PNG_FORMAT_RGB;

    // First call sizes the encoded image, second encodes it into memory.
    png_alloc_size_t size = 0;
    if (!png_image_write_to_memory(&image, nullptr, &size, 0, rgb.data(), 0, nullptr))
        throw input_error(file.path().string(), 0, "", std::string("libpng cannot encode the image: ") + image.message);
    std::unique_ptr<unsigned char[]> encoded(new unsigned char[size]);
    if (!png_image_write_to_memory(&image, encoded.get(), &size, 0, rgb.data(), 0, nullptr))
        throw input_error(file.path().string(), 0, "", std::string("libpng cannot encode the image: ") + image.message);

    file.stream().write(reinterpret_cast<const char*>(encoded.get()), static_cast<std::streamsize>(size));
}

}  // namespace rayverify
