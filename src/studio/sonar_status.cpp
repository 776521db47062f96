#include "studio/sonar_status.h"

#include <chrono>
#include <string>

#include "sonar/output.h"

namespace strata::studio {

namespace fs = std::filesystem;
using nlohmann::json;

json sonar_status(const fs::path& dir) {
  json out = {{"dir", !dir.empty()}, {"latest", nullptr}, {"frame", nullptr}};
  if (dir.empty()) return out;
  std::error_code ec;
  const fs::path png = dir / "latest.png";
  const auto size = fs::file_size(png, ec);
  if (!ec) {
    const auto mtime = fs::last_write_time(png, ec);
    const auto ms = ec ? 0 : std::chrono::duration_cast<std::chrono::milliseconds>(mtime.time_since_epoch()).count();
    out["latest"] = {{"bytes", size}, {"mtime_ms", ms}};
  }
  // The newest line of sonar.jsonl: the end summary once there is one, else
  // the newest frame's.
  const sonar::LastLines last = sonar::read_last_lines(dir);
  json line = json::parse(last.end.empty() ? last.frame : last.end, nullptr, false);
  if (!line.is_discarded()) out["frame"] = std::move(line);
  return out;
}

}  // namespace strata::studio
