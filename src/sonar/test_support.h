#pragma once
// TEST-ONLY support for the Sonar Manager's tests and benchmark; never
// linked into strata. Two pieces:
//
// PingSynth: a stand-in for the vehicle's scanning sonar, until the real one
// is ready (its constants follow config/phoenix.toml's [tank] and [sonar]).
// A rectangular tank (walls at x = 0, x = tank_x_m, y = 0, y = tank_y_m), a
// vehicle at (x, y) with a heading, possibly drifting, an optional upright
// cylinder; a beam sweeping back and forth about the bow. Each ping's bins:
// seeded exponential speckle, ringing in the first bins, an echo (Gaussian
// over the bins, one bin wide) at the first surface the beam's centre meets,
// its strength times the cosine of the incidence (the cylinder: whenever it
// is within the beam's width), and rare random spikes.
//
// TestServer: one TCP connection on 127.0.0.1 and a free port, served by a
// script on a thread of its own; sends are bounded in time and timed.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <random>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "protocol/sonar_frame.h"
#include "sonar/manager.h"

namespace strata::sonar {
// Outcomes by name in test failures.
inline void PrintTo(Outcome outcome, std::ostream* os) { *os << outcome_name(outcome); }
}  // namespace strata::sonar

namespace strata::sonar::testing {

struct SynthTarget {
  double x_m = 0.0;
  double y_m = 0.0;
  double radius_m = 0.15;
};

struct SynthConfig {
  double tank_x_m = 12.0;
  double tank_y_m = 8.0;
  double x_m = 7.0;  // north wall 3.5 m away, east wall 5 m
  double y_m = 4.5;
  double heading_deg = 45.0;
  double vx_mps = 0.0;  // the vehicle's drift, tank frame
  double vy_mps = 0.0;
  double range_m = 10.0;
  int bins = 200;
  double sweep_half_deg = 60.0;
  double step_deg = 1.8;
  double beam_width_deg = 1.8;
  double ping_interval_s = 0.05;
  std::optional<SynthTarget> target;
  std::uint64_t seed = 1;
  double noise_mean = 8.0;   // exponential speckle
  double wall_echo = 180.0;  // at normal incidence
  double target_echo = 200.0;
  double spike_rate = 0.0002;  // per bin
};

class PingSynth {
 public:
  explicit PingSynth(SynthConfig config);

  // The next ping: the sweep starts at -sweep_half_deg, turning to starboard.
  protocol::SonarPing next();
  // Pings until (and with) the last one of the n-th complete sweep from now.
  std::vector<protocol::SonarPing> sweeps(int n);

  // From the vehicle's present position along compass angle `compass_deg`:
  // the range to the tank's wall, and to the cylinder seen by a beam of the
  // configured width (nullopt: missed).
  double wall_range(double compass_deg) const;
  std::optional<double> target_range(double compass_deg) const;

  const SynthConfig& config() const { return config_; }
  double x_m() const { return x_m_; }
  double y_m() const { return y_m_; }

 private:
  SynthConfig config_;
  std::mt19937_64 random_;
  double bearing_deg_;
  int direction_ = 1;
  std::uint32_t seq_ = 0;
  double time_s_ = 0.0;
  double x_m_, y_m_;
};

// The server's end of the one connection.
class TestConnection {
 public:
  explicit TestConnection(int fd) : fd_(fd) {}
  // Sends all of `bytes`; false if a send blocked for more than the bound
  // (SO_SNDTIMEO, 10 s) or failed. Records the longest single send.
  bool send(std::string_view bytes);
  bool send(const protocol::SonarFrame& frame) { return send(protocol::encode_sonar(frame)); }
  // Waits (at most `bound_s`) for the reader to close its end; true if it did.
  bool wait_for_close(double bound_s);
  // Closes with a reset (RST) instead of an orderly close.
  void reset();
  double longest_send_s() const { return longest_send_s_; }

 private:
  int fd_;
  double longest_send_s_ = 0.0;
  friend class TestServer;
};

class TestServer {
 public:
  using Script = std::function<void(TestConnection&)>;
  // Listens on a free port; a thread accepts one connection (waiting at most
  // 20 s), runs the script, then closes the connection (FIN unless reset).
  // `send_buffer_bytes` > 0: SO_SNDBUF of the connection.
  explicit TestServer(Script script, int send_buffer_bytes = 0);
  ~TestServer();
  TestServer(const TestServer&) = delete;
  TestServer& operator=(const TestServer&) = delete;

  std::uint16_t port() const { return port_; }
  void join();
  bool accepted() const { return accepted_.load(); }

 private:
  int listener_ = -1;
  std::uint16_t port_ = 0;
  std::atomic<bool> accepted_{false};
  std::thread thread_;
};

// A port on 127.0.0.1 that nothing listens on (bound, then closed).
std::uint16_t closed_port();

// An empty folder of the test's own under the temporary folder.
std::filesystem::path fresh_dir(std::string_view name);

// Manager options for a test: the loopback port, a 5 s connect timeout, a
// fresh folder named `dir_name`, log lines dropped.
ManagerOptions options_for(std::uint16_t port, const std::string& dir_name);

}  // namespace strata::sonar::testing
