#include "tactical/mission_log.h"

#include <algorithm>
#include <cassert>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>
#include <ext/stdio_filebuf.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include <fmt/format.h>

namespace strata::tactical {

using nlohmann::ordered_json;

namespace {

std::string dump(const ordered_json& j) {
  // replace: text from a mission (a REPORT string) may hold invalid UTF-8;
  // the log must take it rather than throw.
  return j.dump(-1, ' ', false, ordered_json::error_handler_t::replace);
}

void strip(ordered_json& j) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end();) {
      if (it.key().rfind("wall_", 0) == 0) {
        it = j.erase(it);
      } else {
        strip(it.value());
        ++it;
      }
    }
  } else if (j.is_array()) {
    for (auto& e : j) strip(e);
  }
}

}  // namespace

WallTimeSource WallTimeSource::system() {
  // The one place the mission log's wall fields meet the real clocks.
  return {[] { return std::chrono::system_clock::now(); }, [] { return std::chrono::steady_clock::now(); }};
}

double log_time(double sim_time_s) {
  if (!std::isfinite(sim_time_s)) return sim_time_s;
  return std::round(sim_time_s * 1e6) / 1e6;
}

std::string iso8601_utc(std::chrono::system_clock::time_point t) {
  using namespace std::chrono;
  auto us = duration_cast<microseconds>(t.time_since_epoch()).count();
  auto secs = us / 1000000;
  auto frac = us % 1000000;
  if (frac < 0) {
    frac += 1000000;
    secs -= 1;
  }
  std::time_t tt = static_cast<std::time_t>(secs);
  std::tm tm{};
  gmtime_r(&tt, &tm);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:06}Z", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                     tm.tm_hour, tm.tm_min, tm.tm_sec, frac);
}

ordered_json run_header(const RunInfo& run, std::chrono::system_clock::time_point wall_time) {
  ordered_json j;
  j["event"] = "run";
  j["version"] = run.version;
  j["mission"] = run.mission;
  j["mission_sha256"] = run.mission_sha256;
  j["data"] = run.data.empty() ? ordered_json(nullptr) : ordered_json(run.data);
  j["data_sha256"] = run.data.empty() ? ordered_json(nullptr) : ordered_json(run.data_sha256);
  j["scenario"] = run.scenario;
  j["seed"] = run.seed;
  if (!run.params.empty()) {
    j["params"] = run.params;
    j["params_sha256"] = run.params_sha256;
  }
  if (!run.param_overrides.empty()) {
    ordered_json overrides = ordered_json::object();
    for (const auto& [name, value] : run.param_overrides) overrides[name] = value;
    j["param_overrides"] = std::move(overrides);
  }
  j["clock"] = run.clock;
  j["wall_time"] = iso8601_utc(wall_time);
  return j;
}

MissionLog::MissionLog(std::unique_ptr<std::ostream> owned, std::ostream* out, std::string path, WallTimeSource wall)
    : owned_(std::move(owned)), out_(out), path_(std::move(path)), wall_(std::move(wall)) {}

core::Result<MissionLog> MissionLog::start(MissionLog log, const RunInfo& run) {
  if (run.clock != "lockstep" && run.clock != "wall") {
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("mission log: clock must be \"lockstep\" or \"wall\", not \"{}\"", run.clock));
  }
  log.write(run_header(run, log.wall_.now()));
  if (auto s = log.status(); !s) return s.error();
  return log;
}

namespace {

// The most dated logs of one mission in one second (open_dated).
constexpr int kMaxDatedLogs = 100'000;

// An output stream over a file descriptor it owns (closed with it).
class FdStream final : public std::ostream {
 public:
  explicit FdStream(int fd) : std::ostream(nullptr), buf_(fd, std::ios::out | std::ios::binary) { rdbuf(&buf_); }

 private:
  __gnu_cxx::stdio_filebuf<char> buf_;
};

// Opens path for the log: O_NOFOLLOW (a link at the name is refused),
// O_NONBLOCK (a FIFO never blocks the open), then only a regular file is
// kept, and emptied only then. `exclusive`: only a new file.
core::Result<int> open_log_file(const std::string& path, bool exclusive) {
  const int fd =
      ::open(path.c_str(), O_WRONLY | O_CREAT | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK | (exclusive ? O_EXCL : 0), 0644);
  if (fd < 0) {
    const int e = errno;
    if (e == EEXIST) return core::make_error(core::ErrorCode::Overflow, fmt::format("{}: exists", path));
    return core::make_error(core::ErrorCode::Io,
                            fmt::format("{}: cannot create the mission log: {}", path,
                                        e == ELOOP ? "it is a symbolic link (not written through)" : std::strerror(e)));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return core::make_error(core::ErrorCode::Io,
                            fmt::format("{}: cannot create the mission log: not a regular file", path));
  }
  if ((!exclusive && ::ftruncate(fd, 0) != 0) || ::fcntl(fd, F_SETFL, 0) != 0) {
    const int e = errno;
    ::close(fd);
    return core::make_error(core::ErrorCode::Io,
                            fmt::format("{}: cannot create the mission log: {}", path, std::strerror(e)));
  }
  return fd;
}

}  // namespace

core::Result<MissionLog> MissionLog::open(const std::string& path, const RunInfo& run, WallTimeSource wall) {
  auto fd = open_log_file(path, /*exclusive=*/false);
  if (!fd) return fd.error();
  auto file = std::make_unique<FdStream>(fd.value());
  std::ostream* out = file.get();
  return start(MissionLog(std::move(file), out, path, std::move(wall)), run);
}

core::Result<MissionLog> MissionLog::open_dated(const std::string& folder, const std::string& mission,
                                                const RunInfo& run, WallTimeSource wall) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec || !fs::is_directory(folder, ec)) {
    return core::make_error(core::ErrorCode::Io, fmt::format("{}: cannot make the log folder: {}", folder,
                                                             ec ? ec.message() : "not a folder"));
  }
  const auto now = std::chrono::system_clock::now();
  const auto path_of = [&](int n) { return (fs::path(folder) / dated_log_name(mission, now, n)).string(); };
  const auto taken = [&](int n) {
    struct stat st {};
    return ::lstat(path_of(n).c_str(), &st) == 0;
  };
  // The names of a second are taken 1, 2, 3...: probe up by doubling past
  // those taken, then halve back to a free one, so a script's 1,000th run
  // in one second looks at about 20 names, not 1,000. A name another run
  // takes between the look and the open moves this one on to the next.
  int below = 0, free = 1;
  while (free <= kMaxDatedLogs && taken(free)) below = free, free *= 2;
  free = std::min(free, kMaxDatedLogs + 1);
  while (free - below > 1) {
    const int mid = below + (free - below) / 2;
    (taken(mid) ? below : free) = mid;
  }
  for (int n = free; n <= kMaxDatedLogs; ++n) {
    const std::string path = path_of(n);
    auto fd = open_log_file(path, /*exclusive=*/true);
    if (!fd && fd.error().code == core::ErrorCode::Overflow) continue;  // taken: the next name
    if (!fd) return fd.error();
    auto file = std::make_unique<FdStream>(fd.value());
    std::ostream* out = file.get();
    return start(MissionLog(std::move(file), out, path, std::move(wall)), run);
  }
  return core::make_error(core::ErrorCode::Io,
                          fmt::format("{}: {} logs of '{}' in one second already; not logging", folder, kMaxDatedLogs,
                                      fs::path(mission).filename().string()));
}

std::string dated_log_name(const std::string& mission, std::chrono::system_clock::time_point utc, int n) {
  const std::time_t t = std::chrono::system_clock::to_time_t(utc);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%SZ", &tm);
  std::string file = std::filesystem::path(mission).filename().string();
  if (file.empty()) file = "run";
  return n <= 1 ? fmt::format("{}-{}.jsonl", stamp, file) : fmt::format("{}-{}-{}.jsonl", stamp, file, n);
}

core::Result<MissionLog> MissionLog::to_stream(std::ostream& out, const RunInfo& run, WallTimeSource wall) {
  return start(MissionLog(nullptr, &out, "<stream>", std::move(wall)), run);
}

void MissionLog::limit(std::uint64_t max_bytes, std::function<void()> on_full) {
  max_bytes_ = max_bytes;
  on_full_ = std::move(on_full);
}

void MissionLog::write(const ordered_json& line) {
  assert(line.is_object());
  if (failure_) return;
  write_text(dump(line) + '\n');
}

void MissionLog::write(LogLine&& line) {
  if (failure_) return;
  write_text(std::move(line).finish());
}

void MissionLog::write_text(const std::string& text) {
  if (max_bytes_ > 0) {
    if (bytes_ + text.size() > max_bytes_) {
      ++dropped_;
      return;
    }
    const std::uint64_t reserve = std::min<std::uint64_t>(max_bytes_ / 8, std::uint64_t{1} << 20);
    if (!full_ && bytes_ + text.size() > max_bytes_ - reserve) {
      full_ = true;
      ordered_json note;
      note["event"] = "log_limit";
      note["max_bytes"] = max_bytes_;
      note["bytes"] = bytes_;
      std::string said = dump(note) + '\n';
      out_->write(said.data(), static_cast<std::streamsize>(said.size()));
      bytes_ += said.size();
      ++lines_;
      if (on_full_) on_full_();
    }
  }
  out_->write(text.data(), static_cast<std::streamsize>(text.size()));
  out_->flush();
  if (!*out_) {
    failure_ = core::make_error(core::ErrorCode::Io, fmt::format("{}: write to the mission log failed", path_));
    return;
  }
  ++lines_;
  bytes_ += text.size();
}

void MissionLog::request(std::uint64_t id, std::string_view primitive, std::string_view message, double sim_time_s) {
  pending_[id] = Pending{sim_time_s, wall_.monotonic()};
  LogLine line("request");
  line.add("id", id).add("primitive", primitive).add("message", message).add("sim_time", log_time(sim_time_s));
  write(std::move(line));
}

void MissionLog::reply(std::uint64_t id, const ordered_json& result, double sim_time_s) {
  LogLine line("reply");
  line.add("id", id).add("result", result).add("sim_time", log_time(sim_time_s));
  auto it = pending_.find(id);
  if (it == pending_.end()) {
    line.add_null("latency_sim_s").add_null("wall_latency_us");
  } else {
    line.add("latency_sim_s", log_time(sim_time_s - it->second.sim_time_s));
    auto wall = std::chrono::duration_cast<std::chrono::microseconds>(wall_.monotonic() - it->second.wall);
    line.add("wall_latency_us", static_cast<std::int64_t>(wall.count()));
    pending_.erase(it);
  }
  write(std::move(line));
}

void MissionLog::telemetry(double sim_time_s, const ordered_json& fields) {
  assert(fields.is_object() || fields.is_null());
  ordered_json j;
  j["event"] = "telemetry";
  j["sim_time"] = log_time(sim_time_s);
  if (fields.is_object()) {
    for (const auto& [k, v] : fields.items()) j[k] = v;
  }
  write(j);
}

void MissionLog::report(std::string_view text, double sim_time_s) {
  ordered_json j;
  j["event"] = "report";
  j["text"] = text;
  j["sim_time"] = log_time(sim_time_s);
  write(j);
}

void MissionLog::error(std::string_view message, double sim_time_s) {
  ordered_json j;
  j["event"] = "error";
  j["message"] = message;
  j["sim_time"] = log_time(sim_time_s);
  write(j);
}

void MissionLog::event(std::string_view name, const ordered_json& fields) {
  assert(fields.is_object() || fields.is_null());
  ordered_json j;
  j["event"] = name;
  if (fields.is_object()) {
    for (const auto& [k, v] : fields.items()) {
      assert(k != "event");
      j[k] = v;
    }
  }
  write(j);
}

core::Result<void> MissionLog::status() const {
  if (failure_) return *failure_;
  return {};
}

std::string strip_wall_fields(std::string_view line) {
  ordered_json j = ordered_json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return std::string(line);
  strip(j);
  return dump(j);
}

std::string strip_wall_fields_from_log(std::string_view text) {
  std::string out;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    std::string_view line = text.substr(start, end == std::string_view::npos ? end : end - start);
    out += strip_wall_fields(line);
    out += '\n';
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return out;
}

}  // namespace strata::tactical
