#pragma once
// 8-bit grey PNG files (libpng): the scan frames the Sonar Manager writes,
// and reading them back (tests, tools).
#include <filesystem>
#include <string>

#include "core/result.h"
#include "sonar/scan_image.h"

namespace strata::sonar {

// The image as PNG bytes (fast deflate: a frame is written several times a
// second).
core::Result<std::string> encode_png(const GreyImage& image);

// A PNG file as 8-bit grey (colour is converted, alpha dropped, 16 bits
// reduced): ErrorCode::Io when it cannot be read, InvalidInput when it is
// not a PNG.
core::Result<GreyImage> read_png(const std::filesystem::path& path);

}  // namespace strata::sonar
