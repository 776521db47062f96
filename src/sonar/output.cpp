#include "sonar/output.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <string_view>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "core/file.h"
#include "sonar/png_io.h"

namespace strata::sonar {

std::string scan_file_name(std::uint64_t frame) { return fmt::format("scan_{:05}.png", frame); }

core::Result<OutputDir> OutputDir::open(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir, ec)) {
    return core::make_error(core::ErrorCode::Io, fmt::format("cannot create the folder {}: {}", dir.string(),
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
  // Whole for the studio that shows them; not synced: one comes several
  // times a second, and the next replaces it.
  const core::WriteOptions not_synced{.durable = false};
  if (auto r = core::write_file_atomically(dir_ / name, png.value(), not_synced); !r) return r.error();
  if (auto r = core::write_file_atomically(dir_ / "latest.png", png.value(), not_synced); !r) return r.error();
  return name;
}

core::Result<void> OutputDir::append_line(const std::string& json) {
  if (std::fwrite(json.data(), 1, json.size(), log_.get()) != json.size() || std::fputc('\n', log_.get()) == EOF ||
      std::fflush(log_.get()) != 0) {
    return core::make_error(core::ErrorCode::Io,
                            fmt::format("cannot write {}: {}", (dir_ / "sonar.jsonl").string(), std::strerror(errno)));
  }
  return {};
}

LastLines read_last_lines(const std::filesystem::path& dir, std::size_t tail_bytes) {
  LastLines out;
  // A regular file only, opened without waiting: a FIFO or a device at the
  // name (the studio's /api/sonar asks about a folder it did not make when
  // given --sonar) reads as no lines, never as a wait.
  const int fd = ::open((dir / "sonar.jsonl").c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) return out;
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return out;
  }
  const off_t size = st.st_size;
  const off_t from = size > static_cast<off_t>(tail_bytes) ? size - static_cast<off_t>(tail_bytes) : 0;
  std::string text(static_cast<std::size_t>(size - from), '\0');
  std::size_t got = 0;
  while (got < text.size()) {
    const ssize_t n = ::pread(fd, text.data() + got, text.size() - got, from + static_cast<off_t>(got));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  ::close(fd);
  text.resize(got);
  // Whole lines only: after the first newline when the tail starts mid-file,
  // up to the last newline.
  std::size_t begin = 0;
  if (from > 0) {
    begin = text.find('\n');
    if (begin == std::string::npos) return out;
    ++begin;
  }
  const std::size_t end = text.rfind('\n');
  if (end == std::string::npos || end < begin) return out;
  std::string_view lines(text.data() + begin, end - begin);
  while (!lines.empty()) {
    const std::size_t nl = lines.find('\n');
    const std::string_view line = lines.substr(0, nl);
    if (line.find("\"event\":\"end\"") != std::string_view::npos) {
      out.end = std::string(line);
    } else if (line.find("\"event\":\"frame\"") != std::string_view::npos) {
      out.frame = std::string(line);
    }
    if (nl == std::string_view::npos) break;
    lines.remove_prefix(nl + 1);
  }
  return out;
}

}  // namespace strata::sonar
