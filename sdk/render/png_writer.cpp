// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/png_writer.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include <png.h>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

struct Sink {
  std::vector<uint8_t>* out;
};

void write_bytes(png_structp png, png_bytep data, png_size_t size) {
  auto* sink = static_cast<Sink*>(png_get_io_ptr(png));
  sink->out->insert(sink->out->end(), data, data + size);
}

void flush_nothing(png_structp) {}

// libpng reports errors through longjmp; this error function records the message and jumps.
struct ErrorState {
  std::string message;
};

void on_error(png_structp png, png_const_charp message) {
  auto* state = static_cast<ErrorState*>(png_get_error_ptr(png));
  if (state != nullptr) state->message = message != nullptr ? message : "unknown libpng error";
  png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {}

}  // namespace

std::vector<uint8_t> encode_png(const uint8_t* rgba, int width, int height) {
  if (width < 1 || height < 1) fail(Status::invalid_argument, "a PNG needs at least one pixel");
  std::vector<uint8_t> out;
  out.reserve(size_t(width) * size_t(height));
  Sink sink{&out};
  ErrorState state;
  std::vector<png_const_bytep> rows(static_cast<size_t>(height), nullptr);
  for (int y = 0; y < height; ++y) rows[size_t(y)] = rgba + 4 * size_t(y) * size_t(width);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, on_error, on_warning);
  if (png == nullptr) fail(Status::out_of_memory, "png_create_write_struct failed");
  png_infop info = png_create_info_struct(png);
  volatile bool failed = false;
  // No C++ object with a destructor may be created between setjmp and the end of libpng use.
  if (info == nullptr) {
    failed = true;
    state.message = "png_create_info_struct failed";
  } else if (setjmp(png_jmpbuf(png))) {
    failed = true;
  } else {
    png_set_write_fn(png, &sink, write_bytes, flush_nothing);
    // Level 6 with adaptive filters: a 1024 x 1024 render is a few hundred KB.
    png_set_compression_level(png, 6);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_write_image(png, const_cast<png_bytepp>(rows.data()));
    png_write_end(png, nullptr);
  }
  png_destroy_write_struct(&png, info != nullptr ? &info : nullptr);
  if (failed) fail(Status::internal_error, "libpng: " + state.message);
  return out;
}

void write_png_file(const std::string& path, const uint8_t* rgba, int width, int height) {
  const std::vector<uint8_t> bytes = encode_png(rgba, width, height);
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "wb"), std::fclose);
  if (!file) fail(Status::io_error, "cannot open '" + path + "' for writing: " + std::strerror(errno));
  if (std::fwrite(bytes.data(), 1, bytes.size(), file.get()) != bytes.size())
    fail(Status::io_error, "cannot write '" + path + "': " + std::strerror(errno));
  FILE* raw = file.release();
  if (std::fclose(raw) != 0) fail(Status::io_error, "cannot write '" + path + "': " + std::strerror(errno));
}

CAGEKIT_NAMESPACE_END
