#include "report/png_image.h"

#include <png.h>

#include <csetjmp>
#include <exception>
#include <cstdio>
#include <ostream>

#include <fmt/format.h>

#include "core/input_error.h"

namespace rayverify {

// libpng reports errors by longjmp to the setjmp of the call in progress.
// Each call below is made from a function with no C++ object whose
// destructor the jump could skip; the error text is kept for the exception.
struct png_writer::encoder {
    std::ostream* out = nullptr;
    std::string name;
    int width = 0, height = 0, rows = 0;
    png_structp png = nullptr;
    png_infop info = nullptr;
    char error[256] = {};
    std::exception_ptr write_failure;  // what the stream threw: kept, never thrown through libpng's C frames
    bool finished = false;

    static void on_error(png_structp png, png_const_charp message) {
        auto* self = static_cast<encoder*>(png_get_error_ptr(png));
        std::snprintf(self->error, sizeof self->error, "%s", message);
        png_longjmp(png, 1);
    }
    static void on_warning(png_structp, png_const_charp) {}
    static void on_write(png_structp png, png_bytep data, png_size_t size) {
        auto* self = static_cast<encoder*>(png_get_io_ptr(png));
        bool written = false;
        try {
            written = static_cast<bool>(self->out->write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size)));
        } catch (...) {
            self->write_failure = std::current_exception();
        }
        if (!written) png_error(png, "cannot write the file");
    }
    static void on_flush(png_structp png) {
        auto* self = static_cast<encoder*>(png_get_io_ptr(png));
        bool flushed = false;
        try {
            flushed = static_cast<bool>(self->out->flush());
        } catch (...) {
            self->write_failure = std::current_exception();
        }
        if (!flushed) png_error(png, "cannot write the file");
    }

    [[noreturn]] void fail() const {
        if (write_failure) std::rethrow_exception(write_failure);
        throw input_error(name, 0, "", fmt::format("PNG: {}", error));
    }

    // Each returns false when libpng failed (the message is in `error`).
    bool start() {
        if (setjmp(png_jmpbuf(png))) return false;
        png_set_write_fn(png, this, on_write, on_flush);
        png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
                     PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
        png_write_info(png, info);
        return true;
    }
    bool row(const std::uint8_t* rgb) {
        if (setjmp(png_jmpbuf(png))) return false;
        png_write_row(png, rgb);
        return true;
    }
    bool end() {
        if (setjmp(png_jmpbuf(png))) return false;
        png_write_end(png, nullptr);
        png_write_flush(png);
        return true;
    }
};

png_writer::png_writer(std::ostream& out, std::string name, int width, int height)
    : encoder_(std::make_unique<encoder>()) {
    encoder& e = *encoder_;
    e.out = &out;
    e.name = std::move(name);
    e.width = width;
    e.height = height;
    if (width <= 0 || height <= 0)
        throw input_error(e.name, 0, "", fmt::format("PNG: no image of {} by {} pixels", width, height));
    e.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &e, encoder::on_error, encoder::on_warning);
    if (e.png) e.info = png_create_info_struct(e.png);
    if (!e.png || !e.info) throw input_error(e.name, 0, "", "PNG: libpng cannot start an image (out of memory)");
    if (!e.start()) e.fail();
}

png_writer::~png_writer() {
    if (encoder_ && encoder_->png) png_destroy_write_struct(&encoder_->png, &encoder_->info);
}

void png_writer::write_row(std::span<const std::uint8_t> rgb) {
    encoder& e = *encoder_;
    if (rgb.size() != static_cast<std::size_t>(e.width) * 3)
        throw input_error(e.name, 0, "",
                          fmt::format("PNG: a row of {} bytes, expected {} ({} pixels)", rgb.size(), e.width * 3, e.width));
    if (e.rows == e.height) throw input_error(e.name, 0, "", fmt::format("PNG: more than {} rows", e.height));
    if (!e.row(rgb.data())) e.fail();
    ++e.rows;
}

void png_writer::finish() {
    encoder& e = *encoder_;
    if (e.rows != e.height)
        throw input_error(e.name, 0, "", fmt::format("PNG: {} rows written of {}", e.rows, e.height));
    if (!e.finished && !e.end()) e.fail();
    e.finished = true;
}

}  // namespace rayverify
