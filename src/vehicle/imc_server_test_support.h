#pragma once
// `strata vehicle --imc`'s tests' rig and peer (imc_server_test.cpp: the
// session; imc_server_steering_test.cpp: steering): the vehicle runs on its
// own thread at --speed 50; the tests wait for events (a message, a state),
// never for a wall-clock time: the wall limit below only ends a test whose
// vehicle is broken, far above what a run needs.
#include <gtest/gtest.h>

#include <sys/socket.h>
#include <poll.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <functional>
#include <future>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "imc/codec.h"
#include "vehicle/imc_server.h"
#include "vehicle/imc_vehicle.h"

namespace strata::vehicle::imc_server_tests {

using asio::ip::udp;
using namespace std::chrono_literals;

inline constexpr std::uint16_t kVehicleId = 0x2C01;
inline constexpr std::uint16_t kPeerId = 0x4001;
inline constexpr std::uint8_t kPeerEnt = 7;
// A broken vehicle ends a wait after this long; a working one answers in
// milliseconds, so a busy machine never reaches it.
inline constexpr auto kWallLimit = 120s;

// The simulated vehicle and its IMC server, on a thread of their own.
class Rig {
 public:
  // lockstep_wait: a lockstep vehicle (ImcServerOptions::lockstep) waiting
  // that long for an unanswered cycle.
  explicit Rig(Scenario scenario = Scenario::nominal(), std::size_t max_peers = 16,
               std::optional<std::chrono::milliseconds> lockstep_wait = std::nullopt)
      : sim_(default_params(), std::move(scenario)), server_(io_, sim_, options(max_peers, lockstep_wait)) {
    auto r = server_.start();
    EXPECT_TRUE(r.ok());
    thread_ = std::thread([this] { io_.run(); });
  }
  ~Rig() {
    asio::post(io_, [this] {
      server_.stop();
      io_.stop();
    });
    thread_.join();
  }
  std::uint16_t port() const { return server_.port(); }
  // Runs f on the vehicle's thread and returns its result.
  template <typename F>
  auto on_loop(F f) {
    std::promise<decltype(f())> p;
    asio::post(io_, [&] { p.set_value(f()); });
    return p.get_future().get();
  }
  ImcServerCounts counts() {
    return on_loop([this] { return server_.counts(); });
  }
  ImcVehicleCounts vehicle_counts() {
    return on_loop([this] { return server_.vehicle().counts(); });
  }
  std::size_t peers() {
    return on_loop([this] { return server_.peer_count(); });
  }
  // The vehicle's clock, as its packets stamp it.
  double timestamp() {
    return on_loop([this] { return server_.vehicle().timestamp(); });
  }
  // Returns once the vehicle has read n datagrams in all (false past
  // kWallLimit: a broken vehicle). A datagram is acted on as it is read.
  bool wait_read(std::uint64_t n);

 private:
  static ImcServerOptions options(std::size_t max_peers, std::optional<std::chrono::milliseconds> lockstep_wait) {
    ImcServerOptions o;
    o.speed = 50.0;
    o.max_peers = max_peers;
    o.lockstep = lockstep_wait.has_value();
    o.lockstep_wait = lockstep_wait.value_or(o.lockstep_wait);
    return o;
  }

  Simulation sim_;
  asio::io_context io_;
  ImcVehicleServer server_;
  std::thread thread_;
};

// A scripted controller: a UDP socket on loopback whose reader thread keeps
// every packet received, in order, so none is lost while the test thinks.
class TestPeer {
 public:
  explicit TestPeer(std::uint16_t vehicle_port, std::uint16_t id = kPeerId)
      : id_(id),
        socket_(io_, udp::endpoint(asio::ip::make_address("127.0.0.1"), 0)),
        vehicle_(asio::ip::make_address("127.0.0.1"), vehicle_port) {
    int big = 8 << 20;
    setsockopt(socket_.native_handle(), SOL_SOCKET, SO_RCVBUF, &big, sizeof big);
    reader_ = std::thread([this] { read(); });
  }
  ~TestPeer() {
    stop_ = true;
    reader_.join();
  }

  void send(imc::Message m, std::uint16_t dst = kVehicleId, double timestamp = 1.0) {
    imc::Packet p;
    p.header.src = id_;
    p.header.src_ent = kPeerEnt;
    p.header.dst = dst;
    p.header.dst_ent = imc::kAnyEntity;
    p.header.timestamp = timestamp;
    p.message = std::move(m);
    auto bytes = imc::encode(p);
    ASSERT_TRUE(bytes.ok());
    send_raw(bytes.value());
  }
  void send_raw(const std::vector<std::uint8_t>& bytes) { socket_.send_to(asio::buffer(bytes), vehicle_); }
  void announce() {
    imc::Announce a;
    a.sys_name = "test-peer";
    a.sys_type = imc::Announce::kSysTypeCcu;
    a.services = "imc+udp://127.0.0.1:" + std::to_string(socket_.local_endpoint().port()) + "/";
    send(a, imc::kNullId);
  }

  // The next packet (after the last one a wait returned) carrying a T for
  // which pred holds; nullopt if none came within kWallLimit.
  template <typename T>
  std::optional<T> wait_for(std::function<bool(const T&)> pred = {}) {
    std::unique_lock lock(mutex_);
    const auto deadline = std::chrono::steady_clock::now() + kWallLimit;
    while (true) {
      for (; cursor_ < packets_.size(); ++cursor_) {
        const auto* m = std::get_if<T>(&packets_[cursor_].message);
        if (m && (!pred || pred(*m))) {
          ++cursor_;
          return *m;
        }
      }
      if (cv_.wait_until(lock, deadline) == std::cv_status::timeout && cursor_ == packets_.size()) {
        return std::nullopt;
      }
    }
  }
  // Waits for n more EstimatedStates: n cycles of simulated time.
  void cycles(int n) {
    for (int i = 0; i < n; ++i) ASSERT_TRUE(wait_for<imc::EstimatedState>());
  }
  // Waits until a packet stamped later than vehicle time t has come: the
  // vehicle's packets come in the order it sent them (one socket, loopback),
  // so every packet it sent up to t has come too. Skips what it waited past.
  bool wait_past(double t) {
    std::unique_lock lock(mutex_);
    const auto deadline = std::chrono::steady_clock::now() + kWallLimit;
    while (true) {
      for (; cursor_ < packets_.size(); ++cursor_) {
        if (packets_[cursor_].header.timestamp > t) {
          ++cursor_;
          return true;
        }
      }
      if (cv_.wait_until(lock, deadline) == std::cv_status::timeout && cursor_ == packets_.size()) return false;
    }
  }
  std::vector<imc::Packet> packets() const {
    std::lock_guard lock(mutex_);
    return packets_;
  }
  template <typename T>
  std::size_t count() const {
    std::lock_guard lock(mutex_);
    std::size_t n = 0;
    for (const auto& p : packets_) n += std::holds_alternative<T>(p.message);
    return n;
  }
  std::size_t undecodable() const {
    std::lock_guard lock(mutex_);
    return undecodable_;
  }
  std::size_t received_now() const {
    std::lock_guard lock(mutex_);
    return packets_.size();
  }

 private:
  void read() {
    std::vector<std::uint8_t> buf(65536);
    while (!stop_) {
      // Every 50 ms, a look at stop_.
      pollfd ready{socket_.native_handle(), POLLIN, 0};
      if (::poll(&ready, 1, 50) <= 0) continue;
      udp::endpoint from;
      asio::error_code ec;
      const std::size_t n = socket_.receive_from(asio::buffer(buf), from, 0, ec);
      if (ec) continue;
      auto d = imc::decode(std::span<const std::uint8_t>(buf.data(), n));
      std::lock_guard lock(mutex_);
      if (auto* p = std::get_if<imc::Packet>(&d)) {
        packets_.push_back(std::move(*p));
      } else {
        ++undecodable_;
      }
      cv_.notify_all();
    }
  }

  std::uint16_t id_;
  asio::io_context io_;
  udp::socket socket_;
  udp::endpoint vehicle_;
  std::thread reader_;
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<imc::Packet> packets_;
  std::size_t cursor_ = 0;
  std::size_t undecodable_ = 0;
};

inline bool Rig::wait_read(std::uint64_t n) {
  const auto deadline = std::chrono::steady_clock::now() + kWallLimit;
  while (counts().datagrams < n) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(1ms);
  }
  return true;
}

// Sends m and returns once the vehicle has acted on it and the peer has
// every packet the vehicle sent until then, whatever the machine's load:
// what m made the vehicle send (or not) can be counted after it.
inline void send_and_settle(Rig& rig, TestPeer& peer, imc::Message m) {
  const auto read = rig.counts().datagrams;
  peer.send(std::move(m));
  ASSERT_TRUE(rig.wait_read(read + 1));
  ASSERT_TRUE(peer.wait_past(rig.timestamp()));
}

inline imc::PlanControl start_plan(std::uint16_t request_id, float timeout_s, std::uint16_t control_src = kPeerId) {
  imc::FollowReference fr;
  fr.control_src = control_src;
  fr.control_ent = kPeerEnt;
  fr.timeout = timeout_s;
  fr.loiter_radius = 5;
  imc::PlanManeuver man;
  man.maneuver_id = "follow";
  man.data = fr;
  imc::PlanSpecification spec;
  spec.plan_id = "strata";
  spec.start_man_id = "follow";
  spec.maneuvers.push_back(man);
  imc::PlanControl pc;
  pc.type = imc::PlanControl::kRequest;
  pc.op = imc::PlanControl::kStart;
  pc.request_id = request_id;
  pc.plan_id = "strata";
  pc.arg = spec;
  return pc;
}

// A Reference to (lat, lon) from the last EstimatedState (the origin
// displaced by its x, y) at depth_m, 0.5 m/s.
inline imc::Reference reference_here(const imc::EstimatedState& s, double depth_m, std::uint8_t extra_flags = 0) {
  imc::Reference r;
  r.flags = imc::Reference::kFlagLocation | imc::Reference::kFlagSpeed | imc::Reference::kFlagZ | extra_flags;
  r.lat = s.lat + s.x / kEarthRadiusM;
  r.lon = s.lon + s.y / (kEarthRadiusM * std::cos(s.lat));
  r.speed = imc::DesiredSpeed{0.5, imc::DesiredSpeed::kSpeedUnitsMetersPs};
  r.z = imc::DesiredZ{static_cast<float>(depth_m), imc::DesiredZ::kZUnitsDepth};
  return r;
}

// Announced, a plan started and its two replies read.
inline void start(TestPeer& peer, float timeout_s = 0) {
  peer.announce();
  ASSERT_TRUE(peer.wait_for<imc::Announce>());
  peer.send(start_plan(11, timeout_s));
  ASSERT_TRUE(peer.wait_for<imc::PlanControl>([](const auto& pc) { return pc.info == "executing maneuver"; }));
}

// Dives to depth_m with a Reference where the vehicle is and waits until an
// EstimatedState is within 0.3 m of it.
inline imc::EstimatedState dive(TestPeer& peer, double depth_m) {
  auto here = peer.wait_for<imc::EstimatedState>();
  EXPECT_TRUE(here);
  if (!here) return {};
  peer.send(reference_here(*here, depth_m));
  auto there = peer.wait_for<imc::EstimatedState>([&](const auto& s) { return std::abs(s.depth - depth_m) < 0.3; });
  EXPECT_TRUE(there);
  return there.value_or(imc::EstimatedState{});
}

inline std::uint16_t crc16_ibm(const std::uint8_t* p, std::size_t n) {
  std::uint16_t crc = 0;
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= p[i];
    for (int b = 0; b < 8; ++b) crc = (crc & 1) ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001) : crc >> 1;
  }
  return crc;
}

}  // namespace strata::vehicle::imc_server_tests
