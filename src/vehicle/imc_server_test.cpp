// `strata vehicle --imc` spoken to by a scripted IMC peer over loopback UDP.
// The vehicle runs on its own thread at --speed 50; the tests wait for
// events (a message, a state), never for a wall-clock time: the wall limits
// below only end a test whose vehicle is broken, far above what a run needs.
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

namespace strata::vehicle {
namespace {

using asio::ip::udp;
using namespace std::chrono_literals;

constexpr std::uint16_t kVehicleId = 0x2C01;
constexpr std::uint16_t kPeerId = 0x4001;
constexpr std::uint8_t kPeerEnt = 7;
// A broken vehicle ends a wait after this long; a working one answers in
// milliseconds, so a busy machine never reaches it.
constexpr auto kWallLimit = 120s;

// The simulated vehicle and its IMC server, on a thread of their own.
class Rig {
 public:
  explicit Rig(Scenario scenario = Scenario::nominal(), std::size_t max_peers = 16)
      : sim_(default_params(), std::move(scenario)), server_(io_, sim_, options(max_peers)) {
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

 private:
  static ImcServerOptions options(std::size_t max_peers) {
    ImcServerOptions o;
    o.speed = 50.0;
    o.max_peers = max_peers;
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

  void send(imc::Message m, std::uint16_t dst = kVehicleId) {
    imc::Packet p;
    p.header.src = id_;
    p.header.src_ent = kPeerEnt;
    p.header.dst = dst;
    p.header.dst_ent = imc::kAnyEntity;
    p.header.timestamp = 1.0;
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

imc::PlanControl start_plan(std::uint16_t request_id, float timeout_s, std::uint16_t control_src = kPeerId) {
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
imc::Reference reference_here(const imc::EstimatedState& s, double depth_m, std::uint8_t extra_flags = 0) {
  imc::Reference r;
  r.flags = imc::Reference::kFlagLocation | imc::Reference::kFlagSpeed | imc::Reference::kFlagZ | extra_flags;
  r.lat = s.lat + s.x / kEarthRadiusM;
  r.lon = s.lon + s.y / (kEarthRadiusM * std::cos(s.lat));
  r.speed = imc::DesiredSpeed{0.5, imc::DesiredSpeed::kSpeedUnitsMetersPs};
  r.z = imc::DesiredZ{static_cast<float>(depth_m), imc::DesiredZ::kZUnitsDepth};
  return r;
}

// Announced, a plan started and its two replies read.
void start(TestPeer& peer, float timeout_s = 0) {
  peer.announce();
  ASSERT_TRUE(peer.wait_for<imc::Announce>());
  peer.send(start_plan(11, timeout_s));
  ASSERT_TRUE(peer.wait_for<imc::PlanControl>([](const auto& pc) { return pc.info == "executing maneuver"; }));
}

// Dives to depth_m with a Reference where the vehicle is and waits until an
// EstimatedState is within 0.3 m of it.
imc::EstimatedState dive(TestPeer& peer, double depth_m) {
  auto here = peer.wait_for<imc::EstimatedState>();
  EXPECT_TRUE(here);
  if (!here) return {};
  peer.send(reference_here(*here, depth_m));
  auto there = peer.wait_for<imc::EstimatedState>([&](const auto& s) { return std::abs(s.depth - depth_m) < 0.3; });
  EXPECT_TRUE(there);
  return there.value_or(imc::EstimatedState{});
}

std::uint16_t crc16_ibm(const std::uint8_t* p, std::size_t n) {
  std::uint16_t crc = 0;
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= p[i];
    for (int b = 0; b < 8; ++b) crc = (crc & 1) ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001) : crc >> 1;
  }
  return crc;
}

TEST(ImcVehicleServer, SilentUntilAPeerAnnouncesThenStreams) {
  Rig rig;
  TestPeer peer(rig.port());
  peer.send(imc::Heartbeat{});
  peer.send(start_plan(1, 0));
  peer.send_raw({1, 2, 3});
  peer.announce();
  auto a = peer.wait_for<imc::Announce>();
  ASSERT_TRUE(a);
  EXPECT_EQ("phoenix-sim", a->sys_name);
  EXPECT_EQ(imc::Announce::kSysTypeUuv, a->sys_type);
  EXPECT_NE(std::string::npos, a->services.find("imc+udp://127.0.0.1:"));
  // Nothing came before the Announce: what was sent unannounced was dropped unread.
  const auto first = peer.packets().front();
  EXPECT_TRUE(std::holds_alternative<imc::Announce>(first.message));
  EXPECT_EQ(kVehicleId, first.header.src);
  EXPECT_EQ(0, first.header.src_ent);
  EXPECT_GE(first.header.timestamp, kImcEpochS);
  auto c = rig.counts();
  EXPECT_EQ(4u, c.datagrams);
  EXPECT_EQ(2u, c.dropped.by_reason[static_cast<std::size_t>(imc::Drop::Filtered)]);
  EXPECT_EQ(1u, c.dropped.by_reason[static_cast<std::size_t>(imc::Drop::Truncated)]);
  EXPECT_EQ(0u, c.accepted);

  ASSERT_TRUE(peer.wait_for<imc::Heartbeat>());
  ASSERT_TRUE(peer.wait_for<imc::GpsFix>());
  auto vs = peer.wait_for<imc::VehicleState>();
  ASSERT_TRUE(vs);
  EXPECT_EQ(imc::VehicleState::kOpModeService, vs->op_mode);
  auto pcs = peer.wait_for<imc::PlanControlState>();
  ASSERT_TRUE(pcs);
  EXPECT_EQ(imc::PlanControlState::kStateReady, pcs->state);
  EXPECT_TRUE(peer.wait_for<imc::EstimatedState>());
  EXPECT_EQ(0u, peer.count<imc::PlanControl>());
  EXPECT_EQ(0u, peer.undecodable());
  EXPECT_EQ(1u, rig.peers());
}

TEST(ImcVehicleServer, EstimatedStateEveryCycleAndTheSlowerStreamsAtTheirRates) {
  Rig rig;
  TestPeer peer(rig.port());
  peer.announce();
  ASSERT_TRUE(peer.wait_for<imc::Announce>());
  peer.cycles(42);
  const auto packets = peer.packets();
  std::vector<std::size_t> est;
  for (std::size_t i = 0; i < packets.size(); ++i) {
    if (std::holds_alternative<imc::EstimatedState>(packets[i].message)) est.push_back(i);
  }
  ASSERT_GE(est.size(), 42u);
  // 40 cycles (4 simulated seconds) from the first EstimatedState on.
  std::size_t vs = 0, gps = 0, hb = 0, pcs = 0, nu = 0;
  for (std::size_t i = est[0] + 1; i < est[40]; ++i) {
    const auto& m = packets[i].message;
    vs += std::holds_alternative<imc::VehicleState>(m);
    gps += std::holds_alternative<imc::GpsFix>(m);
    hb += std::holds_alternative<imc::Heartbeat>(m);
    pcs += std::holds_alternative<imc::PlanControlState>(m);
    nu += std::holds_alternative<imc::NavigationUncertainty>(m);
  }
  EXPECT_EQ(8u, vs);
  EXPECT_EQ(8u, pcs);
  EXPECT_EQ(4u, gps);
  EXPECT_EQ(4u, hb);
  EXPECT_EQ(40u, nu);  // every cycle, before its EstimatedState
  EXPECT_TRUE(std::holds_alternative<imc::NavigationUncertainty>(packets[est[1] - 1].message));
  // Simulated time in the header, whatever the speed and the machine's load.
  EXPECT_NEAR(4.0, packets[est[40]].header.timestamp - packets[est[0]].header.timestamp, 1e-6);
}

TEST(ImcVehicleServer, PlanStartIsAnsweredAndOnlyTheControlSourceSteers) {
  Rig rig;
  TestPeer peer(rig.port());
  TestPeer other(rig.port(), 0x4002);
  peer.announce();
  other.announce();
  ASSERT_TRUE(peer.wait_for<imc::Announce>());
  ASSERT_TRUE(other.wait_for<imc::Announce>());
  peer.send(start_plan(7, 0), imc::kNullId);  // 0xFFFF: ignored, as DUNE does
  peer.send(start_plan(8, 0), imc::kAnyVehicle);
  auto loaded = peer.wait_for<imc::PlanControl>();
  ASSERT_TRUE(loaded);
  EXPECT_EQ(imc::PlanControl::kSuccess, loaded->type);
  EXPECT_EQ(8, loaded->request_id);
  EXPECT_EQ("strata", loaded->plan_id);
  EXPECT_EQ("plan loaded", loaded->info);
  auto executing = peer.wait_for<imc::PlanControl>();
  ASSERT_TRUE(executing);
  EXPECT_EQ("executing maneuver", executing->info);
  EXPECT_TRUE(peer.wait_for<imc::PlanControlState>(
      [](const auto& s) { return s.state == imc::PlanControlState::kStateExecuting && s.plan_id == "strata"; }));
  EXPECT_TRUE(
      peer.wait_for<imc::VehicleState>([](const auto& s) { return s.op_mode == imc::VehicleState::kOpModeManeuver; }));
  auto wait = peer.wait_for<imc::FollowRefState>();
  ASSERT_TRUE(wait);
  EXPECT_EQ(imc::FollowRefState::kStateWait, wait->state);
  EXPECT_EQ(imc::FollowRefState::kProxFar, wait->proximity);
  EXPECT_EQ(kPeerId, wait->control_src);

  // A Reference from another system is ignored; the controller's is answered once.
  auto here = peer.wait_for<imc::EstimatedState>();
  ASSERT_TRUE(here);
  other.send(reference_here(*here, 2.0));
  peer.send(reference_here(*here, 2.0));
  auto answer = peer.wait_for<imc::FollowRefState>();
  ASSERT_TRUE(answer);
  ASSERT_TRUE(answer->reference);
  EXPECT_EQ(reference_here(*here, 2.0), *answer->reference);
  EXPECT_TRUE(answer->proximity & imc::FollowRefState::kProxXyNear);
  EXPECT_FALSE(answer->proximity & imc::FollowRefState::kProxZNear);
  EXPECT_EQ(imc::FollowRefState::kStateElevator, answer->state);
  const auto vc = rig.vehicle_counts();
  EXPECT_EQ(1u, vc.references);
  EXPECT_EQ(1u, vc.references_ignored);
  EXPECT_EQ(1u, vc.requests_ignored);
  EXPECT_EQ(2u, peer.count<imc::FollowRefState>());

  // STOP: answered, the plan ends, the motors stop.
  imc::PlanControl stop;
  stop.type = imc::PlanControl::kRequest;
  stop.op = imc::PlanControl::kStop;
  stop.request_id = 9;
  stop.plan_id = "strata";
  peer.send(stop);
  auto stopped = peer.wait_for<imc::PlanControl>();
  ASSERT_TRUE(stopped);
  EXPECT_EQ(imc::PlanControl::kSuccess, stopped->type);
  EXPECT_EQ(9, stopped->request_id);
  EXPECT_TRUE(peer.wait_for<imc::VehicleState>(
      [](const auto& s) { return s.op_mode == imc::VehicleState::kOpModeService && s.control_loops == 0; }));
}

TEST(ImcVehicleServer, AReferenceToDepthGetsZNearThenManDoneCompletesThePlan) {
  Rig rig;
  TestPeer peer(rig.port());
  start(peer);
  const auto there = dive(peer, 2.0);
  peer.send(reference_here(there, 2.0));
  auto near = peer.wait_for<imc::FollowRefState>([](const auto& s) { return s.reference.has_value(); });
  ASSERT_TRUE(near);
  EXPECT_EQ(imc::FollowRefState::kProxXyNear | imc::FollowRefState::kProxZNear, near->proximity);
  EXPECT_EQ(imc::FollowRefState::kStateLoiter, near->state);
  // Exactly one FollowRefState per Reference, and the one at the start.
  EXPECT_EQ(3u, peer.count<imc::FollowRefState>());

  peer.send(reference_here(there, 2.0, imc::Reference::kFlagManDone));
  auto done = peer.wait_for<imc::PlanControl>([](const auto& pc) { return pc.type != imc::PlanControl::kRequest; });
  ASSERT_TRUE(done);
  EXPECT_EQ(imc::PlanControl::kSuccess, done->type);
  EXPECT_EQ("plan completed", done->info);
  EXPECT_EQ(11, done->request_id);
  EXPECT_TRUE(peer.wait_for<imc::PlanControlState>([](const auto& s) {
    return s.state == imc::PlanControlState::kStateReady &&
           s.last_outcome == imc::PlanControlState::kLastOutcomeSuccess;
  }));
  EXPECT_TRUE(
      peer.wait_for<imc::VehicleState>([](const auto& s) { return s.op_mode == imc::VehicleState::kOpModeService; }));
}

TEST(ImcVehicleServer, AReferenceNorthDrivesNorthUntilXyNear) {
  Scenario s = Scenario::nominal();
  s.world.open_water = true;
  VehicleParams p = default_params();
  Rig rig(s);
  TestPeer peer(rig.port());
  start(peer);
  auto here = peer.wait_for<imc::EstimatedState>();
  ASSERT_TRUE(here);
  imc::EstimatedState goal = *here;
  goal.x += 40.0f;  // IMC x: north
  auto ref = reference_here(goal, 0.0);
  ref.flags = imc::Reference::kFlagLocation | imc::Reference::kFlagSpeed;
  ref.speed = imc::DesiredSpeed{5.0, imc::DesiredSpeed::kSpeedUnitsMetersPs};  // clamped to the top speed
  peer.send(ref);
  auto going = peer.wait_for<imc::FollowRefState>([](const auto& f) { return f.reference.has_value(); });
  ASSERT_TRUE(going);
  EXPECT_EQ(imc::FollowRefState::kStateGoto, going->state);
  // No z asked: z is near; far from the point.
  EXPECT_EQ(imc::FollowRefState::kProxZNear, going->proximity);
  auto near = peer.wait_for<imc::EstimatedState>([&](const auto& e) { return e.x > here->x + 30.0f; });
  ASSERT_TRUE(near);
  EXPECT_NEAR(here->y, near->y, 5.0);  // not east or west
  EXPECT_LE(near->u, p.top_speed_mps() + 1e-3);
  peer.send(ref);
  auto arrived = peer.wait_for<imc::FollowRefState>([](const auto& f) { return f.reference.has_value(); });
  ASSERT_TRUE(arrived);
  EXPECT_TRUE(arrived->proximity & imc::FollowRefState::kProxXyNear);
  EXPECT_EQ(2u, rig.vehicle_counts().clamped);  // both References' speeds
}

TEST(ImcVehicleServer, ASurfaceReferenceIsElevatorThenHover) {
  Rig rig;
  TestPeer peer(rig.port());
  start(peer);
  const auto there = dive(peer, 2.5);
  peer.send(reference_here(there, 0.0));
  auto up = peer.wait_for<imc::FollowRefState>([](const auto& s) { return s.reference.has_value(); });
  ASSERT_TRUE(up);
  EXPECT_EQ(imc::FollowRefState::kStateElevator, up->state);
  auto near_top = peer.wait_for<imc::EstimatedState>([](const auto& s) { return s.depth < 0.5; });
  ASSERT_TRUE(near_top);
  peer.send(reference_here(*near_top, 0.0));
  auto hover = peer.wait_for<imc::FollowRefState>([](const auto& s) { return s.reference.has_value(); });
  ASSERT_TRUE(hover);
  EXPECT_EQ(imc::FollowRefState::kStateHover, hover->state);
}

TEST(ImcVehicleServer, SilenceBeyondTheTimeoutEndsThePlanAndStopsTheMotors) {
  Rig rig;
  TestPeer peer(rig.port());
  start(peer, 2.0f);
  auto timeout =
      peer.wait_for<imc::FollowRefState>([](const auto& s) { return s.state == imc::FollowRefState::kStateTimeout; });
  ASSERT_TRUE(timeout);
  auto failed = peer.wait_for<imc::PlanControl>();
  ASSERT_TRUE(failed);
  EXPECT_EQ(imc::PlanControl::kFailure, failed->type);
  EXPECT_EQ("reference source timed out", failed->info);
  EXPECT_EQ(11, failed->request_id);
  EXPECT_TRUE(peer.wait_for<imc::PlanControlState>([](const auto& s) {
    return s.state == imc::PlanControlState::kStateReady &&
           s.last_outcome == imc::PlanControlState::kLastOutcomeFailure;
  }));
  auto vs = peer.wait_for<imc::VehicleState>();
  ASSERT_TRUE(vs);
  EXPECT_EQ(imc::VehicleState::kOpModeService, vs->op_mode);
  EXPECT_EQ(0u, vs->control_loops);
  // Timed out 2 simulated seconds after the start, whatever the machine's load.
  const auto packets = peer.packets();
  double start_t = 0, timeout_t = 0;
  for (const auto& p : packets) {
    if (const auto* pc = std::get_if<imc::PlanControl>(&p.message); pc && pc->info == "plan loaded") {
      start_t = p.header.timestamp;
    }
    if (const auto* s = std::get_if<imc::FollowRefState>(&p.message);
        s && s->state == imc::FollowRefState::kStateTimeout) {
      timeout_t = p.header.timestamp;
    }
  }
  EXPECT_NEAR(2.0, timeout_t - start_t, 0.11);
}

TEST(ImcVehicleServer, ALeakIsAnErrorAndFailsThePlan) {
  Scenario s = Scenario::nominal();
  Fault leak;
  leak.kind = FaultKind::Leak;
  leak.at_s = 3.0;
  s.faults.push_back(leak);
  Rig rig(s);
  TestPeer peer(rig.port());
  start(peer);
  // At the leak the plan fails, then the states say why.
  auto failed = peer.wait_for<imc::PlanControl>([](const auto& pc) { return pc.type == imc::PlanControl::kFailure; });
  ASSERT_TRUE(failed);
  EXPECT_EQ(11, failed->request_id);
  EXPECT_EQ("Leak Sensor - Nose: leak detected", failed->info);
  EXPECT_TRUE(peer.wait_for<imc::PlanControlState>([](const auto& p) {
    return p.state == imc::PlanControlState::kStateBlocked &&
           p.last_outcome == imc::PlanControlState::kLastOutcomeFailure;
  }));
  auto error =
      peer.wait_for<imc::VehicleState>([](const auto& v) { return v.op_mode == imc::VehicleState::kOpModeError; });
  ASSERT_TRUE(error);
  EXPECT_EQ(1, error->error_count);
  EXPECT_EQ("Leak Sensor - Nose", error->error_ents);
  EXPECT_EQ("Leak Sensor - Nose: leak detected", error->last_error);
  // A plan started in error fails at once.
  peer.send(start_plan(12, 0));
  auto again = peer.wait_for<imc::PlanControl>(
      [](const auto& pc) { return pc.request_id == 12 && pc.type == imc::PlanControl::kFailure; });
  EXPECT_TRUE(again);
}

TEST(ImcVehicleServer, AbortFailsThePlanAndTheVehicleSurfacesItself) {
  Rig rig;
  TestPeer peer(rig.port());
  start(peer);
  dive(peer, 2.0);
  peer.send(imc::Abort{});
  auto failed = peer.wait_for<imc::PlanControl>([](const auto& pc) { return pc.type == imc::PlanControl::kFailure; });
  ASSERT_TRUE(failed);
  EXPECT_EQ(11, failed->request_id);
  EXPECT_EQ("got abort request", failed->info);
  auto error =
      peer.wait_for<imc::VehicleState>([](const auto& v) { return v.op_mode == imc::VehicleState::kOpModeError; });
  ASSERT_TRUE(error);
  EXPECT_EQ("got abort request", error->last_error);
  EXPECT_TRUE(error->control_loops & imc::VehicleState::kLoopDepth);  // the surface law
  EXPECT_TRUE(
      peer.wait_for<imc::VehicleState>([](const auto& v) { return v.op_mode == imc::VehicleState::kOpModeService; }));
  EXPECT_TRUE(peer.wait_for<imc::EstimatedState>([](const auto& s) { return s.depth < 0.2; }));
  // No plan: a Reference now is ignored.
  auto here = peer.wait_for<imc::EstimatedState>();
  ASSERT_TRUE(here);
  const auto refs_before = peer.count<imc::FollowRefState>();
  peer.send(reference_here(*here, 2.0));
  peer.cycles(3);
  EXPECT_EQ(refs_before, peer.count<imc::FollowRefState>());
  EXPECT_EQ(1u, rig.vehicle_counts().references_ignored);
}

TEST(ImcVehicleServer, GpsFixOnlyAtTheSurfaceInOpenWater) {
  {
    Rig tank;
    TestPeer peer(tank.port());
    peer.announce();
    auto fix = peer.wait_for<imc::GpsFix>();
    ASSERT_TRUE(fix);
    EXPECT_EQ(0, fix->validity);
    EXPECT_EQ(0, fix->satellites);
  }
  Scenario s = Scenario::nominal();
  s.world.open_water = true;
  s.vehicle_x_m = 100.0;  // east
  s.vehicle_y_m = -50.0;  // south
  Rig sea(s);
  TestPeer peer(sea.port());
  peer.announce();
  auto fix = peer.wait_for<imc::GpsFix>();
  ASSERT_TRUE(fix);
  EXPECT_EQ(0x1FF, fix->validity);
  EXPECT_GT(fix->satellites, 0);
  EXPECT_NEAR(kImcOriginLatRad - 50.0 / kEarthRadiusM, fix->lat, 1e-9);
  EXPECT_GT(fix->lon, kImcOriginLonRad);
  auto est = peer.wait_for<imc::EstimatedState>();
  ASSERT_TRUE(est);
  EXPECT_EQ(kImcOriginLatRad, est->lat);
  EXPECT_NEAR(-50.0, est->x, 30.0);  // north, from the launch estimate (10 m per axis)
  EXPECT_NEAR(100.0, est->y, 30.0);  // east
  auto nu = peer.wait_for<imc::NavigationUncertainty>();
  ASSERT_TRUE(nu);
  EXPECT_GT(nu->x, 0.0f);  // open water: the estimate is uncertain
  EXPECT_EQ(nu->x, nu->y);
  // Below the surface, no fix.
  start(peer);
  dive(peer, 1.0);
  EXPECT_TRUE(peer.wait_for<imc::GpsFix>([](const auto& g) { return g.validity == 0 && g.satellites == 0; }));
}

TEST(ImcVehicleServer, GarbageIsCountedAndDroppedAndTheVehicleGoesOn) {
  Rig rig(Scenario::nominal(), 2);
  TestPeer peer(rig.port());
  TestPeer stranger(rig.port(), 0x5000);
  stranger.send(imc::Heartbeat{});  // not announced: filtered
  peer.announce();
  ASSERT_TRUE(peer.wait_for<imc::Announce>());
  imc::Packet hb;
  hb.header.src = kPeerId;
  hb.message = imc::Heartbeat{};
  auto good = imc::encode(hb).value();
  auto bad_crc = good;
  bad_crc.back() ^= 0xFF;
  auto unknown = good;
  unknown[2] = 0x0F;  // mgid 9999
  unknown[3] = 0x27;
  const std::uint16_t crc = crc16_ibm(unknown.data(), imc::kHeaderBytes);
  unknown[imc::kHeaderBytes] = static_cast<std::uint8_t>(crc & 0xFF);
  unknown[imc::kHeaderBytes + 1] = static_cast<std::uint8_t>(crc >> 8);
  auto longer = good;
  longer.push_back(0);
  peer.send_raw({0xFE});
  peer.send_raw(std::vector<std::uint8_t>(60000, 0xAB));
  peer.send_raw(bad_crc);
  peer.send_raw(unknown);
  peer.send_raw(longer);
  peer.send(imc::EntityList{});  // decodes, but nothing to act on
  // Two more peers: the cap is 2.
  TestPeer second(rig.port(), 0x4002);
  TestPeer third(rig.port(), 0x4003);
  second.announce();
  ASSERT_TRUE(second.wait_for<imc::Announce>());
  third.announce();
  // Every datagram above has been read once a request sent after them is answered.
  peer.send(start_plan(20, 0));
  ASSERT_TRUE(peer.wait_for<imc::PlanControl>([](const auto& pc) { return pc.request_id == 20; }));
  const auto c = rig.counts();
  const auto reason = [&](imc::Drop d) { return c.dropped.by_reason[static_cast<std::size_t>(d)]; };
  EXPECT_EQ(1u, reason(imc::Drop::Filtered));
  EXPECT_EQ(1u, reason(imc::Drop::Truncated));
  EXPECT_EQ(1u, reason(imc::Drop::BadSync));
  EXPECT_EQ(1u, reason(imc::Drop::BadCrc));
  EXPECT_EQ(1u, reason(imc::Drop::UnknownId));
  EXPECT_EQ(1u, reason(imc::Drop::BadSize));
  EXPECT_EQ(1u, c.not_acted_on);
  EXPECT_EQ(1u, c.peers_refused);
  EXPECT_EQ(2u, rig.peers());
  EXPECT_TRUE(peer.wait_for<imc::EstimatedState>());
  second.cycles(2);
  EXPECT_EQ(0u, third.count<imc::Announce>());
  EXPECT_EQ(0u, third.received_now());
}

// Without the socket: the coordinates the contract fixes.
TEST(ImcVehicle, ImcXIsNorthAndYIsEastOfTheOrigin) {
  Scenario s = Scenario::nominal();
  s.world.open_water = true;
  s.vehicle_x_m = 30.0;   // east
  s.vehicle_y_m = -20.0;  // south
  VehicleParams p = default_params();
  p.nav_initial_sd_m = 0.0;
  Simulation sim(p, s);
  ImcVehicle v(sim, ImcVehicleOptions{});
  v.step();
  const auto est = v.estimated_state();
  EXPECT_NEAR(-20.0, est.x, 0.05);
  EXPECT_NEAR(30.0, est.y, 0.05);
  const auto [lat, lon] = v.to_lat_lon(30.0, -20.0);
  EXPECT_NEAR(kImcOriginLatRad - 20.0 / kEarthRadiusM, lat, 1e-12);
  EXPECT_NEAR(kImcOriginLonRad + 30.0 / (kEarthRadiusM * std::cos(kImcOriginLatRad)), lon, 1e-12);
  const auto [x, y] = v.to_plan(lat, lon);
  EXPECT_NEAR(30.0, x, 1e-6);
  EXPECT_NEAR(-20.0, y, 1e-6);
  EXPECT_NEAR(1.7e9 + 0.1, v.timestamp(), 1e-6);
}

}  // namespace
}  // namespace strata::vehicle
