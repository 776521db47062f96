#pragma once
// The IMC link's tests' peer and rig (imc_link_test.cpp: the session;
// imc_link_primitives_test.cpp: the primitives): a scripted IMC peer on
// loopback UDP, on one io_context. The peer answers what a DUNE vehicle
// answers (facts measured on its LAUV simulator, docs/imc.md), and the test
// moves the vehicle's clock by sending EstimatedState itself, so nothing
// waits on time except the one silence test.
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

// Named, not anonymous: the unity build puts these tests with
// lockstep_test.cpp, which has a ScriptedVehicle of its own.
namespace strata::tactical::imc_link_tests {

using namespace std::chrono_literals;
using testing::run_until;

inline constexpr std::uint16_t kVehicleId = 0x00D1;
inline constexpr double kEpoch = 1.7e9;

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
  void announce(std::string services = "imc+udp://127.0.0.1:6002/") {
    imc::Announce a;
    a.sys_name = "lauv-simulator-1";
    a.sys_type = imc::Announce::kSysTypeUuv;
    a.services = std::move(services);
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
  void connect(std::string services = "imc+udp://127.0.0.1:6002/") {
    link->connect([this](core::Result<ImcVehicleInfo> r) { connected = std::move(r); });
    ASSERT_TRUE(run_until(io, [&] { return !vehicle.received.empty(); }));
    vehicle.announce(std::move(services));
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

// Lets the link read what the vehicle sent, and the vehicle what the link
// sent (a Reference of the stream may follow a test's own).
inline void settle(ImcRig& rig) {
  run_until(
      rig.io, [] { return false; }, 50ms);
}

// The Reference an exec steered to, once every Reference in flight is in.
inline imc::Reference steered(ImcRig& rig, const std::string& f, std::vector<protocol::Value> args = {}) {
  rig.steer(f, std::move(args));
  settle(rig);
  return rig.vehicle.references.back();
}

}  // namespace strata::tactical::imc_link_tests
