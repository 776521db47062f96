// The IMC link against a scripted IMC peer on loopback UDP, on one
// io_context: the peer answers what a DUNE vehicle answers (facts measured
// on its LAUV simulator, docs/imc.md), and the test moves the vehicle's
// clock by sending EstimatedState itself, so nothing here waits on time
// except the one silence test.
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <asio.hpp>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "imc/codec.h"
#include "tactical/execution_level.h"
#include "tactical/imc_link.h"
#include "tactical/test_rig.h"

namespace strata::tactical {
// Named, beside the anonymous one: the unity build puts this file with
// lockstep_test.cpp, which has a ScriptedVehicle of its own.
namespace imc_link_tests {
namespace {

using namespace std::chrono_literals;
using testing::run_until;

constexpr std::uint16_t kVehicleId = 0x00D1;
constexpr double kEpoch = 1.7e9;

// A vehicle that speaks only what the test makes it say.
class ScriptedVehicle {
 public:
  explicit ScriptedVehicle(asio::io_context& io)
      : socket_(io, asio::ip::udp::endpoint(asio::ip::make_address("127.0.0.1"), 0)) {
    receive();
  }
  std::uint16_t port() const { return socket_.local_endpoint().port(); }

  void send(imc::Message m, std::uint16_t src = kVehicleId) {
    imc::Packet p;
    p.header.timestamp = kEpoch + t_s;
    p.header.src = src;
    p.message = std::move(m);
    auto bytes = imc::encode(p);
    ASSERT_TRUE(bytes.ok());
    send_raw(bytes.value());
  }
  void send_raw(const std::vector<std::uint8_t>& bytes) {
    ASSERT_TRUE(peer_.has_value()) << "the link never wrote to the vehicle";
    socket_.send_to(asio::buffer(bytes), *peer_);
  }
  void announce() {
    imc::Announce a;
    a.sys_name = "lauv-simulator-1";
    a.sys_type = imc::Announce::kSysTypeUuv;
    send(a);
  }
  // One navigation cycle: the clock moves by dt, then EstimatedState.
  void state(double dt = 0.1) {
    t_s += dt;
    imc::EstimatedState es;
    es.lat = 0.7188;  // rad, Leixões
    es.lon = -0.1519;
    es.x = static_cast<float>(north_m);
    es.y = static_cast<float>(east_m);
    es.depth = static_cast<float>(depth_m);
    es.z = es.depth;
    es.alt = 20;
    es.psi = static_cast<float>(psi_rad);
    send(es);
  }
  void vehicle_state(std::uint8_t op_mode, std::string ents = "", std::string error = "") {
    imc::VehicleState vs;
    vs.op_mode = op_mode;
    vs.error_count = op_mode == imc::VehicleState::kOpModeError ? 1 : 0;
    vs.error_ents = std::move(ents);
    vs.last_error = std::move(error);
    send(vs);
  }
  void plan_reply(std::uint8_t type, std::string info) {
    imc::PlanControl pc;
    pc.type = type;
    pc.op = imc::PlanControl::kStart;
    pc.request_id = last_plan_request;
    pc.plan_id = plan_start ? plan_start->plan_id : "";
    pc.info = std::move(info);
    send(pc);
  }
  void plan_state(std::uint8_t state, std::string plan_id) {
    imc::PlanControlState s;
    s.state = state;
    s.plan_id = std::move(plan_id);
    send(s);
  }
  // The FollowRefState DUNE sends for the newest Reference.
  void follow_state(std::uint8_t state, std::uint8_t proximity) {
    ASSERT_FALSE(references.empty());
    imc::FollowRefState f;
    f.control_src = controller;
    f.control_ent = 1;
    f.reference = references.back();
    f.state = state;
    f.proximity = proximity;
    send(f);
  }

  std::vector<imc::Packet> received;
  std::vector<imc::Reference> references;
  std::optional<imc::PlanControl> plan_start;
  std::uint16_t last_plan_request = 0;
  std::uint16_t controller = 0;  // the control_src of the plan started
  int aborts = 0;
  double t_s = 0;
  double north_m = 0, east_m = 0, depth_m = 0, psi_rad = 0;

 private:
  void receive() {
    socket_.async_receive_from(asio::buffer(buffer_), from_, [this](const asio::error_code& e, std::size_t n) {
      if (e) return;
      peer_ = from_;
      auto d = imc::decode(std::span<const std::uint8_t>(buffer_.data(), n));
      if (auto* p = std::get_if<imc::Packet>(&d)) {
        received.push_back(*p);
        if (auto* r = std::get_if<imc::Reference>(&p->message)) references.push_back(*r);
        if (auto* pc = std::get_if<imc::PlanControl>(&p->message)) {
          plan_start = *pc;
          last_plan_request = pc->request_id;
          controller = p->header.src;
        }
        if (std::holds_alternative<imc::Abort>(p->message)) ++aborts;
      }
      receive();
    });
  }
  asio::ip::udp::socket socket_;
  asio::ip::udp::endpoint from_;
  std::optional<asio::ip::udp::endpoint> peer_;
  std::array<std::uint8_t, 65536> buffer_{};
};

struct ImcRig {
  asio::io_context io;
  ScriptedVehicle vehicle{io};
  std::shared_ptr<ImcLink> link;
  std::optional<core::Result<ImcVehicleInfo>> connected;
  std::vector<std::string> faults;
  std::vector<std::string> events;
  std::optional<core::Error> lost;

  explicit ImcRig(ImcLinkOptions o = {}) {
    o.port = vehicle.port();
    link = ImcLink::create(io, o);
    link->on_fault([this](const std::string& why) { faults.push_back(why); });
    link->on_event([this](const protocol::Event& e) { events.push_back(e.text); });
    link->on_lost([this](const core::Error& e) { lost = e; });
  }
  // The DUNE sequence: the link announces, the vehicle announces back and
  // streams its state; the link starts its plan; the vehicle says SUCCESS.
  void connect() {
    link->connect([this](core::Result<ImcVehicleInfo> r) { connected = std::move(r); });
    ASSERT_TRUE(run_until(io, [&] { return !vehicle.received.empty(); }));
    vehicle.announce();
    vehicle.state();
    ASSERT_TRUE(run_until(io, [&] { return vehicle.plan_start.has_value(); }));
    vehicle.plan_reply(imc::PlanControl::kSuccess, "plan loaded");
    ASSERT_TRUE(run_until(io, [&] { return connected.has_value(); }));
    ASSERT_TRUE(connected->ok()) << connected->error().message;
    // The plan's first Reference (hold here) is in, so the next one counted is a test's.
    ASSERT_TRUE(run_until(io, [&] { return !vehicle.references.empty(); }));
  }
  core::Result<protocol::VehicleMessage> call(protocol::Request r, int cycles = 1, double dt = 0.1) {
    std::optional<core::Result<protocol::VehicleMessage>> reply;
    link->send(
        std::move(r), [&](core::Result<protocol::VehicleMessage> m) { reply = std::move(m); }, std::nullopt, 30.0);
    for (int i = 0; i < cycles && !reply; ++i) {
      vehicle.state(dt);
      run_until(
          io, [&] { return reply.has_value(); }, 200ms);
    }
    EXPECT_TRUE(run_until(io, [&] { return reply.has_value(); }));
    if (!reply) return core::make_error(core::ErrorCode::Internal, "no reply within the test's bound");
    return std::move(*reply);
  }
  bool ask(const std::string& q) {
    auto r = call(protocol::make_ask(0, q));
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    auto* a = r.ok() ? std::get_if<protocol::Answer>(&r.value()) : nullptr;
    EXPECT_NE(a, nullptr);
    return a && a->value;
  }
  // An exec that steers: the Reference it sent, once the vehicle has it.
  imc::Reference steer(const std::string& f, std::vector<protocol::Value> args = {}) {
    const std::size_t before = vehicle.references.size();
    EXPECT_TRUE(exec(f, std::move(args)));
    EXPECT_TRUE(run_until(io, [&] { return vehicle.references.size() > before; }));
    return vehicle.references.empty() ? imc::Reference{} : vehicle.references.back();
  }
  bool exec(const std::string& f, std::vector<protocol::Value> args = {}) {
    auto r = call(protocol::make_exec(0, f, std::move(args)));
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    auto* d = r.ok() ? std::get_if<protocol::Done>(&r.value()) : nullptr;
    EXPECT_NE(d, nullptr);
    return d && d->success;
  }
};

TEST(ImcLink, LearnsTheVehicleFromItsAnnounceAndStartsAFollowReferencePlanNamingItself) {
  ImcRig rig;
  rig.connect();
  EXPECT_EQ(rig.connected->value().id, kVehicleId);
  EXPECT_EQ(rig.connected->value().name, "lauv-simulator-1");
  ASSERT_TRUE(rig.vehicle.plan_start);
  const imc::PlanControl& pc = *rig.vehicle.plan_start;
  EXPECT_EQ(pc.type, imc::PlanControl::kRequest);
  EXPECT_EQ(pc.op, imc::PlanControl::kStart);
  const auto* spec = pc.arg.get_if<imc::PlanSpecification>();
  ASSERT_NE(spec, nullptr);
  ASSERT_EQ(spec->maneuvers.size(), 1u);
  const auto* follow = spec->maneuvers[0].data.get_if<imc::FollowReference>();
  ASSERT_NE(follow, nullptr);
  EXPECT_EQ(follow->control_src, rig.link->system_id());
  EXPECT_EQ(rig.link->system_id(), 0x4000 | (rig.link->local_port() & 0x1FFF));  // one id per run
  EXPECT_EQ(follow->control_ent, 1);
  EXPECT_FLOAT_EQ(follow->timeout, 10.0f);
  // The first thing after the plan: hold here (a location, always).
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.vehicle.references.empty(); }));
  EXPECT_TRUE(rig.vehicle.references.back().flags & imc::Reference::kFlagLocation);
  // Before it, the leak sensor monitored: DUNE reports a leak only then.
  bool monitored = false;
  for (const auto& p : rig.vehicle.received) {
    if (const auto* m = std::get_if<imc::MonitorEntityState>(&p.message)) {
      monitored = m->command == imc::MonitorEntityState::kCommandEnable && m->entities == "Leak Sensor - Nose";
    }
    if (std::holds_alternative<imc::PlanControl>(p.message)) break;
  }
  EXPECT_TRUE(monitored);
  // The plan was addressed to the vehicle, not broadcast (DUNE ignores 0xFFFF).
  for (const auto& p : rig.vehicle.received) {
    if (std::holds_alternative<imc::PlanControl>(p.message)) {
      EXPECT_EQ(p.header.dst, kVehicleId);
    }
  }
}

TEST(ImcLink, AVehicleThatNeverAnnouncesIsATimeoutSayingSo) {
  ImcLinkOptions o;
  o.connect_timeout = 300ms;
  ImcRig rig(o);
  rig.link->connect([&](core::Result<ImcVehicleInfo> r) { rig.connected = std::move(r); });
  ASSERT_TRUE(run_until(
      rig.io, [&] { return rig.connected.has_value(); }, 20s));
  ASSERT_FALSE(rig.connected->ok());
  EXPECT_EQ(rig.connected->error().code, core::ErrorCode::Timeout);
  EXPECT_NE(rig.connected->error().message.find("no Announce"), std::string::npos) << rig.connected->error().message;
}

TEST(ImcLink, APlanRefusedByTheVehicleIsAnErrorWithItsReason) {
  ImcRig rig;
  rig.link->connect([&](core::Result<ImcVehicleInfo> r) { rig.connected = std::move(r); });
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.vehicle.received.empty(); }));
  rig.vehicle.announce();
  rig.vehicle.state();
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.plan_start.has_value(); }));
  rig.vehicle.plan_reply(imc::PlanControl::kFailure, "vehicle in ERROR");
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.connected.has_value(); }));
  ASSERT_FALSE(rig.connected->ok());
  EXPECT_EQ(rig.connected->error().message, "the IMC vehicle refused the plan: vehicle in ERROR");
}

TEST(ImcLink, GotoDepthIsAReferenceWithZAndIsAnsweredAtTheNextStateOnTheVehiclesClock) {
  ImcRig rig;
  rig.connect();
  const double before = rig.vehicle.t_s;
  const std::size_t sent = rig.vehicle.references.size();
  auto r = rig.call(protocol::make_exec(0, "goto_depth", {protocol::Value::real(2.5)}));
  ASSERT_TRUE(r.ok());
  const auto& done = std::get<protocol::Done>(r.value());
  EXPECT_TRUE(done.success);
  // The run's clock starts at the first EstimatedState (0.1 s of the
  // vehicle's); the reply comes with the next one, 0.1 s after `before`.
  EXPECT_DOUBLE_EQ(done.sim_time_s, before);
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.references.size() > sent; }));
  const imc::Reference& ref = rig.vehicle.references.back();
  EXPECT_EQ(ref.flags & 0x07, imc::Reference::kFlagLocation | imc::Reference::kFlagSpeed | imc::Reference::kFlagZ);
  ASSERT_TRUE(ref.z);
  EXPECT_FLOAT_EQ(ref.z->value, 2.5f);
  EXPECT_EQ(ref.z->z_units, imc::DesiredZ::kZUnitsDepth);
}

TEST(ImcLink, DepthReachedNeedsZNearForTheReferenceSentAndThePhoenixsTolerance) {
  ImcRig rig;
  rig.connect();
  ASSERT_TRUE(rig.exec("goto_depth", {protocol::Value::integer(2)}));
  rig.vehicle.depth_m = 1.5;  // DUNE says Z_NEAR within 1 m: not yet reached for the Phoenix's 0.1 m
  rig.vehicle.follow_state(imc::FollowRefState::kStateGoto, imc::FollowRefState::kProxZNear);
  EXPECT_FALSE(rig.ask("depth_reached"));
  rig.vehicle.depth_m = 1.97;
  rig.vehicle.follow_state(imc::FollowRefState::kStateGoto, imc::FollowRefState::kProxZNear);
  EXPECT_TRUE(rig.ask("depth_reached"));
  // A new target: the old echo says nothing about it.
  ASSERT_TRUE(rig.exec("goto_depth", {protocol::Value::integer(4)}));
  EXPECT_FALSE(rig.ask("depth_reached"));
}

TEST(ImcLink, GotoXyIsAPointNorthEastOfTheOriginAndWaypointReachedIsXyNear) {
  ImcRig rig;
  rig.connect();
  const imc::Reference ref =
      rig.steer("goto_xy", {protocol::Value::integer(100), protocol::Value::integer(0)});  // east
  EXPECT_NEAR(ref.lat, 0.7188, 1e-9);
  EXPECT_NEAR(ref.lon, -0.1519 + 100.0 / (6378137.0 * std::cos(0.7188)), 1e-12);
  EXPECT_FALSE(rig.ask("waypoint_reached"));
  rig.vehicle.follow_state(imc::FollowRefState::kStateLoiter,
                           imc::FollowRefState::kProxXyNear | imc::FollowRefState::kProxZNear);
  EXPECT_TRUE(rig.ask("waypoint_reached"));
}

TEST(ImcLink, TelemetryIsInStratasFrameXEastYNorth) {
  ImcRig rig;
  rig.connect();
  std::vector<protocol::Telemetry> seen;
  rig.link->on_telemetry([&](const protocol::Telemetry& t) { seen.push_back(t); });
  ASSERT_TRUE(rig.call(protocol::make_telemetry(0, 10)).ok());
  ASSERT_TRUE(run_until(rig.io, [&] { return !seen.empty(); }));
  const std::size_t before = seen.size();
  rig.vehicle.north_m = 10;
  rig.vehicle.east_m = 5;
  rig.vehicle.depth_m = 1.25;
  rig.vehicle.psi_rad = std::numbers::pi / 2;
  rig.vehicle.state(1.0);  // past the next sample's time at 10 Hz
  ASSERT_TRUE(run_until(rig.io, [&] { return seen.size() > before; }));
  EXPECT_EQ(seen.back().extras["x"], "5");
  EXPECT_EQ(seen.back().extras["y"], "10");
  EXPECT_DOUBLE_EQ(*seen.back().depth_m, 1.25);
  EXPECT_NEAR(*seen.back().heading_deg, 90.0, 1e-4);
}

TEST(ImcLink, SleepEndsOnTheVehiclesClockNotTheWallClock) {
  ImcRig rig;
  rig.connect();
  const double start = rig.vehicle.t_s;
  // Cycles of 1 s of the vehicle's time each: the reply comes at the first
  // state at least 3 s after the call, however fast they come.
  auto r = rig.call(protocol::make_exec(0, "sleep", {protocol::Value::integer(3)}), 10, 1.0);
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(std::get<protocol::Done>(r.value()).sim_time_s - (start - 0.1), 3.0, 1e-9);
}

TEST(ImcLink, TheReferenceStreamStaysAliveAtTwiceASecondOfTheVehiclesTime) {
  ImcRig rig;
  rig.connect();
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.vehicle.references.empty(); }));
  const std::size_t before = rig.vehicle.references.size();
  for (int i = 0; i < 100; ++i) rig.vehicle.state(0.1);  // 10 s of the vehicle's time
  // A Reference each 0.5 s of it: 20, the last one sent when the last state arrives.
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.references.size() - before >= 20; }));
  EXPECT_TRUE(rig.ask("system_problem") == false);  // one more state: at most one more Reference
  EXPECT_LE(rig.vehicle.references.size() - before, 21u);
}

TEST(ImcLink, AVehicleInErrorAnswersSystemProblemAndIsSurfacedByAbort) {
  ImcRig rig;
  rig.connect();
  EXPECT_FALSE(rig.ask("system_problem"));
  rig.vehicle.vehicle_state(imc::VehicleState::kOpModeError, "Leak Sensor - Nose", "Leak Sensor - Nose: leak detected");
  rig.vehicle.plan_reply(imc::PlanControl::kFailure, "vehicle error");
  EXPECT_TRUE(rig.ask("system_problem"));
  EXPECT_TRUE(rig.exec("surface"));
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.aborts > 0; }));
  EXPECT_EQ(rig.vehicle.aborts, 1);
  EXPECT_EQ(rig.link->surface_method(), "abort");
  bool named = false;
  for (const auto& e : rig.events)
    named = named || e == "vehicle in ERROR: Leak Sensor - Nose: Leak Sensor - Nose: leak detected";
  EXPECT_TRUE(named);
}

TEST(ImcLink, SurfaceIsAZeroDepthReferenceWhenTheVehicleTakesOne) {
  ImcRig rig;
  rig.connect();
  const imc::Reference ref = rig.steer("surface");
  ASSERT_TRUE(ref.z);
  EXPECT_EQ(ref.z->value, 0.0f);
  EXPECT_EQ(rig.vehicle.aborts, 0);
  EXPECT_EQ(rig.link->surface_method(), "reference");
}

TEST(ImcLink, APlanReplacedByAnotherControllerIsAFaultNamingBothPlans) {
  ImcRig rig;
  rig.connect();
  // Before the vehicle said it runs ours, a state naming another plan is old news.
  rig.vehicle.plan_state(imc::PlanControlState::kStateExecuting, "survey-neptus");
  EXPECT_FALSE(rig.ask("system_problem"));  // answered after the state above was read
  EXPECT_TRUE(rig.faults.empty());
  rig.vehicle.plan_state(imc::PlanControlState::kStateExecuting, rig.link->plan_id());
  rig.vehicle.plan_state(imc::PlanControlState::kStateExecuting, "survey-neptus");
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.faults.empty(); }));
  EXPECT_EQ(rig.faults[0],
            fmt::format("another controller replaced this run's plan '{}' with 'survey-neptus'", rig.link->plan_id()));
  EXPECT_EQ(rig.link->plan_id(), fmt::format("strata-{}", rig.link->local_port()));
  // Surfacing is then the other controller's call: neither a Reference nor an Abort.
  EXPECT_FALSE(rig.exec("surface"));
  EXPECT_EQ(rig.link->surface_method(), "");
}

TEST(ImcLink, AFollowReferenceTimeoutIsAFaultAndSurfaceStartsANewPlan) {
  ImcRig rig;
  rig.connect();
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.vehicle.references.empty(); }));
  rig.vehicle.follow_state(imc::FollowRefState::kStateTimeout, imc::FollowRefState::kProxFar);
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.faults.empty(); }));
  EXPECT_NE(rig.faults[0].find("FollowReference timed out"), std::string::npos);
  const std::uint16_t first = rig.vehicle.last_plan_request;
  std::optional<core::Result<protocol::VehicleMessage>> reply;
  rig.link->send(protocol::make_exec(0, "surface"), [&](auto m) { reply = std::move(m); });
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.last_plan_request != first; }));
  const std::size_t refs = rig.vehicle.references.size();
  rig.vehicle.plan_reply(imc::PlanControl::kSuccess, "plan loaded");
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.references.size() > refs; }));
  ASSERT_TRUE(rig.vehicle.references.back().z);
  EXPECT_EQ(rig.vehicle.references.back().z->value, 0.0f);
}

TEST(ImcLink, ShutdownEndsThePlanWithManDoneAndIsAnsweredWhenItEnded) {
  ImcRig rig;
  rig.connect();
  std::optional<core::Result<protocol::VehicleMessage>> reply;
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.vehicle.references.empty(); }));
  const std::size_t refs = rig.vehicle.references.size();
  rig.link->send(protocol::make_ood(0, "shutdown_network"), [&](auto m) { reply = std::move(m); });
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.references.size() > refs; }));
  EXPECT_TRUE(rig.vehicle.references.back().flags & imc::Reference::kFlagManDone);
  EXPECT_FALSE(rig.ask("system_problem"));  // a state has passed ...
  EXPECT_FALSE(reply.has_value());          // ... and the plan still runs: no answer yet
  rig.vehicle.plan_reply(imc::PlanControl::kSuccess, "plan completed");
  ASSERT_TRUE(run_until(rig.io, [&] { return reply.has_value(); }));
  ASSERT_TRUE(reply->ok());
  EXPECT_TRUE(std::get<protocol::Done>(reply->value()).success);
  EXPECT_FALSE(rig.link->plan_running());
}

TEST(ImcLink, ASilentVehicleIsLostAndItsCallsFail) {
  ImcLinkOptions o;
  o.lost_after = 200ms;
  ImcRig rig(o);
  rig.connect();
  std::optional<core::Result<protocol::VehicleMessage>> reply;
  rig.link->send(protocol::make_ask(0, "depth_reached"), [&](auto m) { reply = std::move(m); });
  // Only wall time passes: the vehicle says nothing more.
  ASSERT_TRUE(run_until(
      rig.io, [&] { return rig.lost.has_value() && reply.has_value(); }, 30s));
  EXPECT_EQ(rig.lost->code, core::ErrorCode::Closed);
  EXPECT_EQ(rig.lost->message, "no EstimatedState from the IMC vehicle for 200 ms");
  ASSERT_FALSE(reply->ok());
  EXPECT_EQ(reply->error().code, core::ErrorCode::Closed);
}

TEST(ImcLink, GarbageAndOtherSystemsAreCountedNeverUsed) {
  ImcRig rig;
  rig.connect();
  const std::uint64_t used = rig.link->counts().used;
  const std::uint64_t received = rig.link->counts().received;
  rig.vehicle.send_raw({0xFE, 0x54, 1, 2, 3});  // truncated
  imc::Packet heartbeat{{}, imc::Message(imc::Heartbeat{})};
  heartbeat.header.src = kVehicleId;
  std::vector<std::uint8_t> bad = imc::encode(heartbeat).value();
  bad.back() ^= 0xFF;  // CRC
  rig.vehicle.send_raw(bad);
  // Another system on the same address (a second vehicle's id): its state must not move ours.
  rig.vehicle.send(imc::Message(imc::VehicleState{}), 0x0022);
  // A message a controller does not read (EntityState, 53 Hz on DUNE).
  rig.vehicle.send(imc::Message(imc::EntityState{}));
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.link->counts().received >= received + 4; }));
  const ImcCounts& c = rig.link->counts();
  EXPECT_EQ(c.dropped.total(), 2u);
  EXPECT_EQ(c.other_sources, 1u);
  EXPECT_EQ(c.filtered, 1u);
  EXPECT_EQ(c.used, used);
  EXPECT_NE(imc_summary(c).find("1 from others, 2 dropped ("), std::string::npos) << imc_summary(c);
}

TEST(ImcLink, AFloodOfGarbageAndASecondControllerAreCountedAndTheCallsGoOn) {
  ImcLinkOptions o;
  o.lost_after = std::chrono::minutes(1);  // no state comes while the flood is sent: not a lost vehicle
  ImcRig rig(o);
  rig.connect();
  // A second controller on its own socket: everything it sends is another
  // system's, its PlanControl included.
  asio::ip::udp::socket other(rig.io, asio::ip::udp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  const asio::ip::udp::endpoint link_at(asio::ip::make_address("127.0.0.1"), rig.link->local_port());
  imc::PlanControl start;
  start.type = imc::PlanControl::kRequest;
  start.plan_id = "neptus";
  imc::Packet theirs{{}, imc::Message(start)};
  theirs.header.src = 0x4100;
  const auto their_bytes = imc::encode(theirs).value();
  // Garbage from the vehicle's own address: every kind of bad packet.
  auto good = imc::encode(imc::Packet{{0, 0, 0, kVehicleId}, imc::Message(imc::Heartbeat{})}).value();
  std::vector<std::vector<std::uint8_t>> garbage{{0x01}, std::vector<std::uint8_t>(20, 0xAB), good, good, good};
  garbage[2].back() ^= 0x5A;     // CRC
  garbage[3][4] = 0x7F;          // size bigger than the datagram
  garbage[4][2] = 0x39;          // an id no one knows (0x0039... at the header)
  constexpr int kRounds = 2000;  // 10,000 bad datagrams and 2,000 from the other controller
  const std::uint64_t received = rig.link->counts().received;
  const ImcCounts before = rig.link->counts();
  int answered = 0;
  for (int round = 0; round < kRounds; ++round) {
    for (const auto& g : garbage) rig.vehicle.send_raw(g);
    other.send_to(asio::buffer(their_bytes), link_at);
    rig.io.restart();
    rig.io.poll();  // the link reads as it comes, as its loop does
    if (round % 200 == 0) {
      // Still answered, in between (a state lost in a full socket buffer: the next one answers).
      auto r = rig.call(protocol::make_ask(0, "depth_filter_off"), 20);
      answered += r.ok() && std::get<protocol::Answer>(r.value()).value ? 1 : 0;
    }
  }
  EXPECT_EQ(answered, kRounds / 200);
  // UDP may drop some of a flood in the kernel; every datagram that arrives
  // is accounted for: used, filtered at its header, another system's, or
  // dropped under its reason.
  const ImcCounts& c = rig.link->counts();
  EXPECT_EQ(c.received - received, (c.used - before.used) + (c.filtered - before.filtered) +
                                       (c.other_sources - before.other_sources) +
                                       (c.dropped.total() - before.dropped.total()));
  EXPECT_GT(c.other_sources - before.other_sources, 0u);
  for (imc::Drop d : {imc::Drop::Truncated, imc::Drop::BadCrc}) {
    EXPECT_GT(c.dropped.by_reason[static_cast<std::size_t>(d)], 0u) << imc::drop_name(d);
  }
  EXPECT_GT(c.filtered + c.dropped.by_reason[static_cast<std::size_t>(imc::Drop::Truncated)] +
                c.dropped.by_reason[static_cast<std::size_t>(imc::Drop::BadSize)],
            0u);  // the size and the unknown id: seen at the header
  EXPECT_TRUE(rig.faults.empty());
  EXPECT_TRUE(rig.link->plan_running());
  EXPECT_TRUE(rig.exec("goto_depth", {protocol::Value::integer(1)}));
}

TEST(ImcLink, AStepOfTheVehiclesClockEndsNoDeadline) {
  ImcRig rig;
  rig.connect();
  std::optional<core::Result<protocol::VehicleMessage>> reply;
  rig.link->send(
      protocol::make_exec(0, "sleep", {protocol::Value::integer(30)}), [&](auto m) { reply = std::move(m); },
      std::nullopt, 32.0);
  rig.vehicle.state(10000.0);  // the vehicle set its clock from GPS, or one timestamp far off
  rig.vehicle.state(0.1);
  EXPECT_TRUE(rig.ask("depth_filter_off"));  // two states read: the sleep is not over
  EXPECT_FALSE(reply.has_value());
  bool said = false;
  for (const auto& e : rig.events) said = said || e.find("the vehicle's clock stepped by") != std::string::npos;
  EXPECT_TRUE(said);
  // A timestamp that is no time is dropped, not taken as the clock.
  const std::uint64_t dropped = rig.link->counts().dropped.total();
  imc::Packet nan{{}, imc::Message(imc::EstimatedState{})};
  nan.header.src = kVehicleId;
  nan.header.timestamp = std::numeric_limits<double>::quiet_NaN();
  rig.vehicle.send_raw(imc::encode(nan).value());
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.link->counts().dropped.total() > dropped; }));
  EXPECT_FALSE(reply.has_value());
}

TEST(ImcLink, APlanStoppedOutsideTheRunIsAFaultAndSteeringThenSaysZero) {
  ImcRig rig;
  rig.connect();
  rig.vehicle.plan_state(imc::PlanControlState::kStateExecuting, rig.link->plan_id());
  rig.vehicle.plan_state(imc::PlanControlState::kStateReady, rig.link->plan_id());  // an operator's STOP
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.faults.empty(); }));
  EXPECT_NE(rig.faults[0].find("was stopped outside the run"), std::string::npos) << rig.faults[0];
  EXPECT_FALSE(rig.link->plan_running());
  EXPECT_FALSE(rig.exec("goto_depth", {protocol::Value::integer(2)}));  // nothing takes it: 0, not 1
}

TEST(ImcLink, AStartWhoseReplyWasLostIsConfirmedByThePlansState) {
  ImcRig rig;
  rig.link->connect([&](core::Result<ImcVehicleInfo> r) { rig.connected = std::move(r); });
  ASSERT_TRUE(run_until(rig.io, [&] { return !rig.vehicle.received.empty(); }));
  rig.vehicle.announce();
  rig.vehicle.state();
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.vehicle.plan_start.has_value(); }));
  // No PlanControl reply (lost on the way); the periodic state names the plan.
  rig.vehicle.plan_state(imc::PlanControlState::kStateExecuting, rig.vehicle.plan_start->plan_id);
  ASSERT_TRUE(run_until(rig.io, [&] { return rig.connected.has_value(); }));
  ASSERT_TRUE(rig.connected->ok());
  EXPECT_TRUE(rig.link->plan_running());
}

TEST(ImcLink, AFunctionAnImcVehicleHasNotIsRefusedNotSent) {
  ImcRig rig;
  rig.connect();
  auto r = rig.call(protocol::make_exec(0, "set_sway", {protocol::Value::real(0.1)}));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, core::ErrorCode::InvalidInput) << "the link cannot carry it: refused, not a bad reply";
  EXPECT_EQ(r.error().message, "an IMC vehicle has no 'set_sway' (docs/imc.md)");
}

TEST(ImcLink, TheSonarIsAPayloadSwitchedBySetEntityParameters) {
  ImcRig rig;
  rig.connect();
  const std::size_t before = rig.vehicle.received.size();
  EXPECT_TRUE(rig.exec("start_sonar"));
  const imc::SetEntityParameters* set = nullptr;
  ASSERT_TRUE(run_until(rig.io, [&] {
    for (std::size_t i = before; i < rig.vehicle.received.size() && !set; ++i) {
      set = std::get_if<imc::SetEntityParameters>(&rig.vehicle.received[i].message);
    }
    return set != nullptr;
  }));
  EXPECT_EQ(set->name, "Sidescan");
  ASSERT_EQ(set->params.size(), 1u);
  EXPECT_EQ(set->params[0].name, "Active");
  EXPECT_EQ(set->params[0].value, "true");
}

TEST(ImcLink, PositionUncertainIsTheHorizontalSigmaOfNavigationUncertaintyAboveTheLimit) {
  ImcRig rig;
  rig.connect();
  EXPECT_FALSE(rig.ask("position_uncertain"));  // none heard: not uncertain
  imc::NavigationUncertainty nu;
  nu.x = 24.0f * 24.0f;  // the horizontal sigma is sqrt(var_x + var_y): 24.2 m
  nu.y = 10.0f;
  rig.vehicle.send(nu);
  EXPECT_FALSE(rig.ask("position_uncertain"));
  nu.x = 18.0f * 18.0f;  // 18 and 18: 25.5 m, over the limit though neither axis is
  nu.y = 18.0f * 18.0f;
  rig.vehicle.send(nu);
  EXPECT_TRUE(rig.ask("position_uncertain"));
}

// Issue 37's primitives over IMC.

// Lets the link read what the vehicle sent, and the vehicle what the link
// sent (a Reference of the stream may follow a test's own).
void settle(ImcRig& rig) {
  run_until(
      rig.io, [] { return false; }, 50ms);
}

// The Reference an exec steered to, once every Reference in flight is in.
imc::Reference steered(ImcRig& rig, const std::string& f, std::vector<protocol::Value> args = {}) {
  rig.steer(f, std::move(args));
  settle(rig);
  return rig.vehicle.references.back();
}

TEST(ImcLink, RowsAreKeptByTheLinkAndEachNextRowIsAReferenceAtTheRowsEnd) {
  ImcRig rig;
  rig.connect();
  EXPECT_FALSE(rig.ask("rows_done"));  // no pattern
  auto none = rig.call(protocol::make_exec(0, "next_row"));
  ASSERT_TRUE(none.ok());
  auto* err = std::get_if<protocol::Err>(&none.value());
  ASSERT_NE(err, nullptr) << "refused as the Phoenix refuses it: err failed";
  EXPECT_EQ(err->code, protocol::ErrorCode::Failed);
  EXPECT_EQ(err->message, "next_row: no row pattern (start_rows first)");
  using protocol::Value;
  EXPECT_TRUE(rig.exec("start_rows", {Value::integer(0), Value::integer(0), Value::integer(0), Value::integer(100),
                                      Value::integer(20), Value::integer(2)}));
  EXPECT_FALSE(rig.ask("rows_done"));
  // Row 0 runs north from the origin: its end is 100 m north.
  imc::Reference ref = steered(rig, "next_row");
  EXPECT_NEAR(ref.lat, 0.7188 + 100.0 / 6378137.0, 1e-9);
  EXPECT_NEAR(ref.lon, -0.1519, 1e-12);
  EXPECT_FALSE(rig.ask("rows_done"));
  // Row 1 runs back south, 20 m to starboard (east): its end is 20 m east of the origin.
  ref = steered(rig, "next_row");
  EXPECT_NEAR(ref.lat, 0.7188, 1e-9);
  EXPECT_NEAR(ref.lon, -0.1519 + 20.0 / (6378137.0 * std::cos(0.7188)), 1e-12);
  EXPECT_TRUE(rig.ask("rows_done"));
  EXPECT_FALSE(rig.ask("waypoint_reached"));
  rig.vehicle.follow_state(imc::FollowRefState::kStateLoiter,
                           imc::FollowRefState::kProxXyNear | imc::FollowRefState::kProxZNear);
  EXPECT_TRUE(rig.ask("waypoint_reached"));
  auto past = rig.call(protocol::make_exec(0, "next_row"));
  ASSERT_TRUE(past.ok());
  err = std::get_if<protocol::Err>(&past.value());
  ASSERT_NE(err, nullptr);
  EXPECT_EQ(err->message, "next_row: no row left (all 2 rows started)");
  // A bad pattern is a failed exec, with the reason as an event.
  EXPECT_FALSE(rig.exec("start_rows", {Value::integer(0), Value::integer(0), Value::integer(0), Value::integer(100),
                                       Value::integer(20), Value::real(0.5)}));
  EXPECT_EQ(rig.events.back(), "exec start_rows failed: row count 0.5 is not a whole number from 1 to 1000");
}

TEST(ImcLink, SetSpeedIsTheCruiseSpeedOfTheNextGoalAndStopKeepsIt) {
  ImcRig rig;
  rig.connect();
  const std::size_t before = rig.vehicle.references.size();
  EXPECT_TRUE(rig.exec("set_speed", {protocol::Value::real(0.5)}));
  for (int i = 0; i < 3; ++i) rig.vehicle.state();
  settle(rig);
  // No goal: nothing steers, and any Reference of the stream says speed 0.
  for (std::size_t i = before; i < rig.vehicle.references.size(); ++i) {
    ASSERT_TRUE(rig.vehicle.references[i].speed);
    EXPECT_EQ(rig.vehicle.references[i].speed->value, 0.0);
  }
  imc::Reference ref = steered(rig, "goto_xy", {protocol::Value::integer(0), protocol::Value::integer(100)});
  ASSERT_TRUE(ref.speed);
  EXPECT_EQ(ref.speed->value, 0.5);
  ref = steered(rig, "set_speed", {protocol::Value::real(0.7)});  // a goal held: at once
  EXPECT_FLOAT_EQ(static_cast<float>(ref.speed->value), 0.7f);
  ref = steered(rig, "stop");
  EXPECT_EQ(ref.speed->value, 0.0);
  ref = steered(rig, "goto_xy", {protocol::Value::integer(0), protocol::Value::integer(200)});
  EXPECT_FLOAT_EQ(static_cast<float>(ref.speed->value), 0.7f);  // kept through stop
}

TEST(ImcLink, HoldPositionIsAReferenceWhereTheVehicleIs) {
  ImcRig rig;
  rig.connect();
  rig.vehicle.north_m = 30;
  rig.vehicle.east_m = 40;
  rig.vehicle.state();
  settle(rig);
  const imc::Reference ref = steered(rig, "hold_position");
  EXPECT_NEAR(ref.lat, 0.7188 + 30.0 / 6378137.0, 1e-9);
  EXPECT_NEAR(ref.lon, -0.1519 + 40.0 / (6378137.0 * std::cos(0.7188)), 1e-12);
  ASSERT_TRUE(ref.speed);
  EXPECT_FLOAT_EQ(static_cast<float>(ref.speed->value), 0.8f);  // the cruise speed, to come back
  rig.vehicle.follow_state(imc::FollowRefState::kStateLoiter,
                           imc::FollowRefState::kProxXyNear | imc::FollowRefState::kProxZNear);
  EXPECT_TRUE(rig.ask("waypoint_reached"));
}

TEST(ImcLink, SetTimerRunsOnTheVehiclesClock) {
  ImcRig rig;
  rig.connect();
  EXPECT_TRUE(rig.exec("set_timer", {protocol::Value::integer(2)}));
  EXPECT_FALSE(rig.ask("time_out"));
  for (int i = 0; i < 20; ++i) rig.vehicle.state();
  settle(rig);
  EXPECT_TRUE(rig.ask("time_out"));
  EXPECT_FALSE(rig.exec("set_timer", {protocol::Value::integer(0)}));
}

TEST(ImcLink, GpsAvailableIsAFreshValidFixAtTheSurface) {
  ImcRig rig;
  rig.connect();
  EXPECT_FALSE(rig.ask("gps_available"));  // no GpsFix heard
  imc::GpsFix fix;
  fix.validity = 0x1FF;
  fix.satellites = 9;
  rig.vehicle.send(fix);
  settle(rig);
  EXPECT_TRUE(rig.ask("gps_available"));
  for (int i = 0; i < 20; ++i) rig.vehicle.state();  // 2 s without one: stale
  settle(rig);
  EXPECT_FALSE(rig.ask("gps_available"));
  rig.vehicle.send(fix);
  rig.vehicle.depth_m = 2.0;  // under water
  rig.vehicle.state();
  settle(rig);
  EXPECT_FALSE(rig.ask("gps_available"));
  rig.vehicle.depth_m = 0.0;
  fix.validity = 0;  // no fix (DUNE: no satellites)
  fix.satellites = 0;
  rig.vehicle.state();
  rig.vehicle.send(fix);
  settle(rig);
  EXPECT_FALSE(rig.ask("gps_available"));
}

TEST(ImcLink, LoiterIsRefusedNotSent) {
  ImcRig rig;
  rig.connect();
  auto r = rig.call(protocol::make_exec(
      0, "loiter", {protocol::Value::integer(0), protocol::Value::integer(0), protocol::Value::integer(20)}));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "an IMC vehicle has no 'loiter' (docs/imc.md)");
}

TEST(ImcLinkAddress, ParsesHostPortAndAnOptionalId) {
  auto a = parse_imc_vehicle("imc://127.0.0.1:6002");
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a.value().host, "127.0.0.1");
  EXPECT_EQ(a.value().port, 6002);
  EXPECT_FALSE(a.value().vehicle_id);
  auto b = parse_imc_vehicle("imc://localhost:6002/0x00D1");
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(b.value().vehicle_id, 0x00D1);
  EXPECT_EQ(parse_imc_vehicle("imc://localhost:6002/209").value().vehicle_id, 209);
  for (const char* bad : {"imc://", "imc://host", "imc://:6002", "imc://h:0", "imc://h:65536", "imc://h:60x",
                          "imc://h:6002/", "imc://h:6002/0", "imc://h:6002/0xFFFF", "imc://h:6002/zz", "h:6002"}) {
    auto r = parse_imc_vehicle(bad);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_EQ(r.error().code, core::ErrorCode::InvalidInput) << bad;
    EXPECT_NE(r.error().message.find("expected imc://HOST:PORT"), std::string::npos) << r.error().message;
  }
}

TEST(ExecutionLevel, AnImcVehicleRefusesWhatItHasNoCounterpartForAndCarriesTheRest) {
  const Catalogue& c = Catalogue::builtin();
  for (const char* refused : {"target_detected", "set_sway", "loiter"}) {
    ASSERT_NE(c.find(refused), nullptr) << refused;
    EXPECT_TRUE(unavailable_on(ExecutionLevel::Imc, *c.find(refused))) << refused;
    EXPECT_FALSE(unavailable_on(ExecutionLevel::Phoenix, *c.find(refused))) << refused;
  }
  std::size_t carried = 0;
  for (const Primitive& p : c.all()) carried += unavailable_on(ExecutionLevel::Imc, p) ? 0 : 1;
  EXPECT_EQ(carried, c.all().size() - 3);
  EXPECT_NE(unavailable_on(ExecutionLevel::Imc, *c.find("loiter"))->find("FollowReference"), std::string::npos);
  EXPECT_EQ(execution_level_of("imc://127.0.0.1:6002"), ExecutionLevel::Imc);
  EXPECT_EQ(execution_level_of("127.0.0.1:7020"), ExecutionLevel::Phoenix);
}

}  // namespace
}  // namespace imc_link_tests
}  // namespace strata::tactical
