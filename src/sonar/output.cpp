#include "sonar/output.h"

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "sonar/png_io.h"

namespace strata::sonar {

std::string scan_file_name(std::uint64_t frame) { return fmt::format("scan_{:05}.png", frame); }

core::Result<OutputDir> OutputDir::open(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir, ec)) {
    return core::make_error(core::ErrorCode::Io,
                            fmt::format("cannot create the folder {}: {}", dir.string(),
                                        ec ? ec.message() : "a file of that name is in the way"));
  }
  const auto log_path = dir / "sonar.jsonl";
  std::FILE* log = std::fopen(log_path.c_str(), "we");
  if (!log) {
    return core::make_error(core::ErrorCode::Io,
                            fmt::format("cannot write {}: {}", log_path.string(), std::strerror(errno)));
  }
  return OutputDir(dir, log);
}

core::Result<std::string> OutputDir::write_frame(std::uint64_t frame, const GreyImage& image) {
  auto png = encode_png(image);
  if (!png) return png.error();
  std::string name = scan_file_name(frame);
  if (auto r = write_file_atomic(dir_ / name, png.value()); !r) return r.error();
  if (auto r = write_file_atomic(dir_ / "latest.png", png.value()); !r) return r.error();
  return name;
}

core::Result<void> OutputDir::append_line(const std::string& json) {
  if (std::fwrite(json.data(), 1, json.size(), log_.get()) != json.size() || std::fputc('\n', log_.get()) == EOF ||
      std::fflush(log_.get()) != 0) {
    return core::make_error(core::ErrorCode::Io, fmt::format("cannot write {}: {}",
                                                             (dir_ / "sonar.jsonl").string(), std::strerror(errno)));
  }
  return {};
}

}  // namespace strata::sonar
