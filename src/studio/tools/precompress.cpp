// strata_precompress DIR: for every page asset under DIR worth compressing
// (.html .js .css .svg .json .map .txt), writes FILE.gz (zlib, level 9) and
// FILE.br (brotli, quality 11) beside it, once, at build time; the studio
// serves them as they are (src/studio/server.cpp). A variant that is not
// smaller than the file is not written. Exit 0, or 1 with the reason.
#include <brotli/encode.h>
#include <zlib.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <optional>
#include <string>

#include "core/file.h"

namespace fs = std::filesystem;

namespace {

std::optional<std::string> gzip(const std::string& in) {
  z_stream z{};
  // 15 + 16: a gzip wrapper; no name or time in its header (reproducible).
  if (deflateInit2(&z, 9, Z_DEFLATED, 15 + 16, 9, Z_DEFAULT_STRATEGY) != Z_OK) return std::nullopt;
  std::string out(deflateBound(&z, in.size()) + 32, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  z.avail_in = static_cast<uInt>(in.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  const int r = deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  if (r != Z_STREAM_END) return std::nullopt;
  return out;
}

std::optional<std::string> brotli(const std::string& in) {
  std::size_t size = BrotliEncoderMaxCompressedSize(in.size());
  if (size == 0) size = in.size() + 1024;
  std::string out(size, '\0');
  if (!BrotliEncoderCompress(BROTLI_MAX_QUALITY, BROTLI_DEFAULT_WINDOW, BROTLI_MODE_TEXT, in.size(),
                             reinterpret_cast<const uint8_t*>(in.data()), &size,
                             reinterpret_cast<uint8_t*>(out.data()))) {
    return std::nullopt;
  }
  out.resize(size);
  return out;
}

// A variant, when smaller than the file (else nothing is written): true,
// or false with the reason told.
bool write_if_smaller(const fs::path& path, const std::string& bytes, std::size_t original) {
  if (bytes.size() >= original) return true;
  auto written = strata::core::write_file_atomically(path.string(), bytes, {.durable = false});
  if (!written) std::cerr << "strata_precompress: " << written.error().message << "\n";
  return written.ok();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: strata_precompress DIR\n";
    return 1;
  }
  std::error_code ec;
  for (const auto& entry : fs::recursive_directory_iterator(argv[1], ec)) {
    if (!entry.is_regular_file()) continue;
    const fs::path& p = entry.path();
    const std::string ext = p.extension().string();
    if (ext != ".html" && ext != ".js" && ext != ".css" && ext != ".svg" && ext != ".json" && ext != ".map" &&
        ext != ".txt") {
      continue;
    }
    std::ifstream in(p, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    auto gz = gzip(bytes);
    auto br = brotli(bytes);
    if (!gz || !br) {
      std::cerr << "strata_precompress: cannot compress " << p << "\n";
      return 1;
    }
    fs::path gz_path = p, br_path = p;
    gz_path += ".gz";
    br_path += ".br";
    fs::remove(gz_path, ec);
    fs::remove(br_path, ec);
    if (!write_if_smaller(gz_path, *gz, bytes.size()) || !write_if_smaller(br_path, *br, bytes.size())) return 1;
  }
  if (ec) {
    std::cerr << "strata_precompress: " << argv[1] << ": " << ec.message() << "\n";
    return 1;
  }
  return 0;
}
