#pragma once
// The Sonar Manager's folder: DIR/scan_NNNNN.png per frame, DIR/latest.png
// (the newest frame, for a viewer such as the studio), DIR/sonar.jsonl (a
// JSON line per frame, then the end summary). Images are written under a
// temporary name and renamed, so a reader never sees half a file.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "core/result.h"
#include "sonar/scan_image.h"

namespace strata::sonar {

class OutputDir {
 public:
  // Creates `dir` and its parents if need be, and starts DIR/sonar.jsonl
  // afresh (scans of an earlier run are overwritten as frames come).
  static core::Result<OutputDir> open(const std::filesystem::path& dir);

  // Writes the frame's PNG as DIR/scan_NNNNN.png and DIR/latest.png;
  // returns the scan's file name.
  core::Result<std::string> write_frame(std::uint64_t frame, const GreyImage& image);
  // One line (no newline in `json`) in DIR/sonar.jsonl, flushed.
  core::Result<void> append_line(const std::string& json);

  const std::filesystem::path& dir() const { return dir_; }

 private:
  struct Close {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  OutputDir(std::filesystem::path dir, std::FILE* log) : dir_(std::move(dir)), log_(log) {}
  std::filesystem::path dir_;
  std::unique_ptr<std::FILE, Close> log_;
};

std::string scan_file_name(std::uint64_t frame);

// What a reader of DIR/sonar.jsonl wants: the newest frame line and the end
// summary, as JSON text ("" when there is none). Only the file's last
// `tail_bytes` are read, so a long run costs a viewer polling it nothing
// more; a line still being written is ignored.
struct LastLines {
  std::string frame;
  std::string end;
};
LastLines read_last_lines(const std::filesystem::path& dir, std::size_t tail_bytes = std::size_t{64} * 1024);

}  // namespace strata::sonar
