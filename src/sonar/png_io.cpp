#include "sonar/png_io.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>
#include <png.h>

namespace strata::sonar {
namespace {

core::Error io_error(const std::filesystem::path& path, const char* what) {
  return core::make_error(core::ErrorCode::Io,
                          fmt::format("cannot {} {}: {}", what, path.string(), std::strerror(errno)));
}

}  // namespace

core::Result<std::string> encode_png(const GreyImage& image) {
  // libpng's simplified API: errors come back as values, no longjmp.
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_GRAY;
  png.flags = PNG_IMAGE_FLAG_FAST;
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&png, nullptr, &size, 0, image.pixels.data(), 0, nullptr)) {
    return core::make_error(core::ErrorCode::Internal, fmt::format("PNG encoding failed: {}", png.message));
  }
  std::string out(size, '\0');
  if (!png_image_write_to_memory(&png, out.data(), &size, 0, image.pixels.data(), 0, nullptr)) {
    return core::make_error(core::ErrorCode::Internal, fmt::format("PNG encoding failed: {}", png.message));
  }
  out.resize(size);
  return out;
}

core::Result<GreyImage> read_png(const std::filesystem::path& path) {
  if (::access(path.c_str(), R_OK) != 0) return io_error(path, "read");
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) {
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("{}: not a PNG: {}", path.string(), png.message));
  }
  png.format = PNG_FORMAT_GRAY;
  GreyImage image;
  image.width = static_cast<int>(png.width);
  image.height = static_cast<int>(png.height);
  image.pixels.resize(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, image.pixels.data(), 0, nullptr)) {
    png_image_free(&png);
    return core::make_error(core::ErrorCode::InvalidInput, fmt::format("{}: bad PNG: {}", path.string(), png.message));
  }
  return image;
}

}  // namespace strata::sonar
