// TEST-ONLY (see test_support.h).
#include "sonar/test_support.h"

#include <cstdlib>
#include <vector>

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/units.h"
#include "sonar/detect.h"

namespace strata::sonar::testing {

using core::kRadPerDeg;
namespace {

std::uint8_t clamp_byte(double v) { return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L)); }

}  // namespace

PingSynth::PingSynth(SynthConfig config)
    : config_(config), random_(config.seed), bearing_deg_(-config.sweep_half_deg), x_m_(config.x_m), y_m_(config.y_m) {}

double PingSynth::wall_range(double compass_deg) const {
  const double dx = std::sin(compass_deg * kRadPerDeg), dy = std::cos(compass_deg * kRadPerDeg);
  double t = std::numeric_limits<double>::infinity();
  if (dx > 1e-12) t = std::min(t, (config_.tank_x_m - x_m_) / dx);
  if (dx < -1e-12) t = std::min(t, -x_m_ / dx);
  if (dy > 1e-12) t = std::min(t, (config_.tank_y_m - y_m_) / dy);
  if (dy < -1e-12) t = std::min(t, -y_m_ / dy);
  return t;
}

std::optional<double> PingSynth::target_range(double compass_deg) const {
  if (!config_.target) return std::nullopt;
  const auto& c = *config_.target;
  const double dx = c.x_m - x_m_, dy = c.y_m - y_m_;
  const double d = std::hypot(dx, dy);
  if (d <= c.radius_m) return 0.0;
  const double off = std::abs(normalise_deg(compass_deg - std::atan2(dx, dy) / kRadPerDeg)) * kRadPerDeg;
  const double half_angle = std::asin(c.radius_m / d);
  if (off > half_angle + config_.beam_width_deg * kRadPerDeg / 2.0) return std::nullopt;
  if (off <= half_angle) {
    const double s = d * std::sin(off);
    return d * std::cos(off) - std::sqrt(c.radius_m * c.radius_m - s * s);
  }
  return std::sqrt(d * d - c.radius_m * c.radius_m);  // its edge, in the beam's side
}

protocol::SonarPing PingSynth::next() {
  protocol::SonarPing p;
  p.time_s = time_s_;
  p.seq = seq_++;
  p.bearing_deg = static_cast<float>(bearing_deg_);
  p.heading_deg = static_cast<float>(config_.heading_deg);
  p.x_m = static_cast<float>(x_m_);
  p.y_m = static_cast<float>(y_m_);
  p.range_m = static_cast<float>(config_.range_m);
  const auto n = static_cast<std::size_t>(config_.bins);
  const double bin_m = config_.range_m / static_cast<double>(n);
  std::exponential_distribution<double> speckle(1.0 / config_.noise_mean);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> level(n, 0.0);
  for (std::size_t i = 0; i < 3 && i < n; ++i) level[i] = 150.0;              // the transducer's ringing
  const double compass = static_cast<double>(p.heading_deg) + p.bearing_deg;  // as the reader computes it
  const double dx = std::sin(compass * kRadPerDeg), dy = std::cos(compass * kRadPerDeg);
  double range = wall_range(compass);
  const double hit_x = x_m_ + range * dx;
  const bool on_x_wall = std::abs(hit_x) < 1e-6 || std::abs(hit_x - config_.tank_x_m) < 1e-6;
  double strength = config_.wall_echo * std::abs(on_x_wall ? dx : dy);
  if (auto t = target_range(compass); t && *t < range) {
    range = *t;
    strength = config_.target_echo * 0.9;  // a cylinder's face is mostly square to the beam
  }
  const double centre = range / bin_m - 0.5;
  for (long i = std::max(0L, std::lround(centre) - 4); i <= std::lround(centre) + 4 && i < static_cast<long>(n); ++i) {
    const double d = static_cast<double>(i) - centre;
    level[static_cast<std::size_t>(i)] += strength * std::exp(-0.5 * d * d);
  }
  p.bins.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    p.bins[i] = clamp_byte(unit(random_) < config_.spike_rate ? 160.0 : level[i] + speckle(random_));
  }
  // Advance: the sweep turns back at its ends.
  if (std::abs(bearing_deg_ + direction_ * config_.step_deg) > config_.sweep_half_deg + 1e-9) direction_ = -direction_;
  bearing_deg_ += direction_ * config_.step_deg;
  time_s_ += config_.ping_interval_s;
  x_m_ += config_.vx_mps * config_.ping_interval_s;
  y_m_ += config_.vy_mps * config_.ping_interval_s;
  return p;
}

std::vector<protocol::SonarPing> PingSynth::sweeps(int n) {
  std::vector<protocol::SonarPing> out;
  for (int done = 0; done < n && out.size() < 100000;) {
    const int before = direction_;
    out.push_back(next());
    if (direction_ != before) ++done;
  }
  return out;
}

bool TestConnection::send(std::string_view bytes) {
  while (!bytes.empty()) {
    const auto start = std::chrono::steady_clock::now();
    const ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    longest_send_s_ =
        std::max(longest_send_s_, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    if (n <= 0) return false;
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

bool TestConnection::wait_for_close(double bound_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(bound_s);
  char sink[4096];
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, 50) <= 0) continue;
    if (::recv(fd_, sink, sizeof sink, 0) <= 0) return true;
  }
  return false;
}

void TestConnection::reset() {
  linger l{1, 0};
  ::setsockopt(fd_, SOL_SOCKET, SO_LINGER, &l, sizeof l);
  ::close(fd_);
  fd_ = -1;
}

TestServer::TestServer(Script script, int send_buffer_bytes) {
  listener_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  if (listener_ < 0 || ::bind(listener_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
      ::listen(listener_, 1) != 0 || ::getsockname(listener_, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
    return;  // port() stays 0: the test fails to connect
  }
  port_ = ntohs(address.sin_port);
  thread_ = std::thread([this, script = std::move(script), send_buffer_bytes] {
    pollfd p{listener_, POLLIN, 0};
    if (::poll(&p, 1, 20000) <= 0) return;
    const int fd = ::accept4(listener_, nullptr, nullptr, SOCK_CLOEXEC);
    if (fd < 0) return;
    accepted_ = true;
    if (send_buffer_bytes > 0) ::setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &send_buffer_bytes, sizeof send_buffer_bytes);
    timeval bound{10, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &bound, sizeof bound);
    TestConnection connection(fd);
    script(connection);
    if (connection.fd_ >= 0) ::close(connection.fd_);
  });
}

TestServer::~TestServer() {
  join();
  if (listener_ >= 0) ::close(listener_);
}

void TestServer::join() {
  if (thread_.joinable()) thread_.join();
}

std::uint16_t closed_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return 0;  // port 0: refused to connect as well
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  const bool named = ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
                     ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0;
  ::close(fd);
  return named ? ntohs(address.sin_port) : 0;
}

namespace {
// The folders fresh_dir() made, removed when the test process ends (kept
// with STRATA_KEEP_TEST_OUTPUT set, to look at the scans).
struct MadeDirs {
  std::vector<std::filesystem::path> dirs;
  ~MadeDirs() {
    if (std::getenv("STRATA_KEEP_TEST_OUTPUT")) return;
    std::error_code ec;
    for (const auto& d : dirs) std::filesystem::remove_all(d, ec);
  }
};
MadeDirs made_dirs;
}  // namespace

std::filesystem::path fresh_dir(std::string_view name) {
  auto dir =
      std::filesystem::temp_directory_path() / ("strata_sonar_" + std::to_string(::getpid()) + "_" + std::string(name));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  made_dirs.dirs.push_back(dir);
  return dir;
}

ManagerOptions options_for(std::uint16_t port, const std::string& dir_name) {
  ManagerOptions o;
  o.capture.port = port;
  o.capture.connect_timeout_s = 5.0;
  o.out_dir = fresh_dir(dir_name);
  o.log = [](const std::string&) {};
  return o;
}

}  // namespace strata::sonar::testing
