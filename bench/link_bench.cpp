// The Tactical–Execution link in lockstep, both ends in this process as in
// `strata run`: the vehicle server (vehicle::VehicleServer, nominal scenario,
// default params) on its own io_context in its own thread, and the Tactical
// level's tactical::VehicleLink on the benchmark thread's io_context, over
// loopback TCP. Both threads wait in io_context::run()/run_one() (blocked in
// epoll between lines), as the product's event loops do. The `_spinning`
// variants instead busy-poll both io_contexts (poll() in a loop): not what
// the product does, but they show how much of a round trip is the cost of
// waking a sleeping thread, which dominates on small virtual machines.
//
//   link/round_trip/ping   `ping`: the vehicle answers without a cycle, so
//                          this is the link and the transport alone
//   link/round_trip/ask    `ask depth_filter_off`: one 0.1 s simulation
//                          cycle on the vehicle before the answer
//   link/round_trip/ask_spinning
//     Each round trip, send() to its reply handler, is timed on its own with
//     steady_clock (after kWarmupRoundTrips untimed ones); the counters
//     p50_us, p90_us, p99_us and max_us are over every timed round trip, and
//     items_per_second is round trips per second over the whole loop.
//     Target (ask): p50 <= 30 us, p99 <= 100 us.
//
//   link/poll/sleep_1      Figure 10's phase 2 poll: after start_network,
//   link/poll/sleep_0.1    setpoint 0.6 m, the depth filter and submerge, one
//   link/poll/sleep_0.1_spinning
//                          iteration is `exec sleep S`, `ask depth_reached`,
//                          `ask time_out`, `ask system_problem` (S = 1 as the
//                          mission polls, S = 0.1 polling every cycle: the
//                          worst case). The loop keeps polling after the
//                          setpoint is reached (the vehicle holds depth), so a
//                          run covers a fixed number of polls.
//     sim_s_per_wall_s is the simulated time the loop covered (from the
//     replies' SIM_TIME_S) over the wall time it took. Target: >= 1000.
//     items_per_second counts requests.
//
// Iteration counts are fixed, so each benchmark builds one rig and the whole
// binary runs in a few seconds. A request that fails stops its benchmark with
// SkipWithError rather than reporting a figure for work that was not done.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <variant>
#include <vector>

#include <asio.hpp>
#include <fmt/format.h>

#include "protocol/codec.h"
#include "protocol/message.h"
#include "tactical/vehicle_link.h"
#include "vehicle/params.h"
#include "vehicle/scenario.h"
#include "vehicle/server.h"
#include "vehicle/simulation.h"

namespace strata::tactical {
namespace {

using Clock = std::chrono::steady_clock;
using protocol::VehicleMessage;

constexpr benchmark::IterationCount kRoundTrips = 50'000;
constexpr int kWarmupRoundTrips = 2'000;
constexpr benchmark::IterationCount kPolls = 5'000;
constexpr double kSetpointDepthM = 0.6;
// Longer than any run's simulated time, so time_out stays false throughout.
constexpr double kSetpointTimeoutS = 1e6;

// How both threads wait for the next line.
enum class Wait { kBlock, kSpin };

// A vehicle server in its own thread and a connected link on this thread.
class Rig {
 public:
  explicit Rig(Wait wait) : wait_(wait), sim_(vehicle::default_params(), vehicle::Scenario::nominal()) {
    vehicle::ServerOptions options;
    options.clock = protocol::ClockMode::Lockstep;
    server_ = std::make_unique<vehicle::VehicleServer>(vehicle_io_, sim_, options);
    // Started here, before the vehicle thread exists; from then on only that
    // thread touches the server and the simulation.
    if (auto started = server_->start(); !started) {
      problem_ = "vehicle server: " + started.error().message;
      return;
    }
    const std::uint16_t port = server_->port();
    vehicle_thread_ = std::thread([this] {
      if (wait_ == Wait::kBlock) {
        vehicle_io_.run();
      } else {
        // poll() stops the io_context once it is out of work, as run() returns.
        while (!vehicle_io_.stopped()) vehicle_io_.poll();
      }
    });

    LinkOptions link_options;
    link_options.port = port;
    link_ = VehicleLink::create(io_, link_options);
    std::optional<core::Result<protocol::Welcome>> welcome;
    link_->connect([&](core::Result<protocol::Welcome> r) { welcome = std::move(r); });
    while (!welcome && run_once()) {}
    if (!welcome) {
      problem_ = "connect: the client's event loop ran out of work";
    } else if (!welcome->ok()) {
      problem_ = "connect: " + welcome->error().message;
    }
  }

  ~Rig() {
    if (link_) link_->close();
    io_.poll();  // the link's cancelled handlers
    // The server stops on its own thread; run() returns once its handlers
    // have seen the cancellation.
    asio::post(vehicle_io_, [this] { server_->stop(); });
    work_.reset();
    if (vehicle_thread_.joinable()) vehicle_thread_.join();
  }

  Rig(const Rig&) = delete;
  Rig& operator=(const Rig&) = delete;

  // Empty when the rig is up.
  const std::string& problem() const { return problem_; }

  // Sends one request and runs this thread's event loop until its reply.
  core::Result<VehicleMessage> call(protocol::Request request) {
    std::optional<core::Result<VehicleMessage>> reply;
    link_->send(std::move(request), [&](core::Result<VehicleMessage> m) { reply = std::move(m); });
    while (!reply) {
      // The request's timer is work until the reply comes, so this fails
      // only if the link is broken beyond its own timeout handling.
      if (!run_once()) {
        return core::make_error(core::ErrorCode::Internal, "the client's event loop ran out of work");
      }
    }
    return std::move(*reply);
  }

 private:
  // Runs (kBlock) or polls (kSpin) this thread's io_context once; false when
  // it is out of work.
  bool run_once() {
    if (wait_ == Wait::kBlock) return io_.run_one() != 0;
    io_.poll();
    return !io_.stopped();
  }

  Wait wait_;
  vehicle::Simulation sim_;
  asio::io_context vehicle_io_;
  // Keeps the vehicle thread's run() going between connections.
  std::optional<asio::executor_work_guard<asio::io_context::executor_type>> work_{asio::make_work_guard(vehicle_io_)};
  std::unique_ptr<vehicle::VehicleServer> server_;
  std::thread vehicle_thread_;
  asio::io_context io_;
  std::shared_ptr<VehicleLink> link_;
  std::string problem_;
};

// The simulated time a reply carries, or the reason there is none.
struct Timed {
  bool value = false;  // done's success, answer's value
  double sim_time_s = 0.0;
  std::string problem;  // empty on success
};

Timed timed(const core::Result<VehicleMessage>& reply) {
  if (!reply) return {false, 0.0, reply.error().message};
  if (const auto* d = std::get_if<protocol::Done>(&reply.value())) return {d->success, d->sim_time_s, {}};
  if (const auto* a = std::get_if<protocol::Answer>(&reply.value())) return {a->value, a->sim_time_s, {}};
  if (const auto* p = std::get_if<protocol::Pong>(&reply.value())) return {true, p->sim_time_s, {}};
  return {false, 0.0, "unexpected reply: " + protocol::encode(reply.value())};
}

// Sample at quantile q (0..1) of sorted samples, nearest rank.
double quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted.size())));
  return sorted[std::clamp<std::size_t>(rank, 1, sorted.size()) - 1];
}

template <typename MakeRequest>
void bm_round_trip(benchmark::State& st, Wait wait, MakeRequest make_request) {
  Rig rig(wait);
  if (!rig.problem().empty()) {
    st.SkipWithError(rig.problem().c_str());
    return;
  }
  for (int i = 0; i < kWarmupRoundTrips; ++i) {
    Timed t = timed(rig.call(make_request()));
    if (!t.problem.empty()) {
      st.SkipWithError(("warm-up: " + t.problem).c_str());
      return;
    }
  }
  std::vector<double> us;
  us.reserve(static_cast<std::size_t>(st.max_iterations));
  for (auto _ : st) {
    protocol::Request request = make_request();
    Clock::time_point start = Clock::now();
    core::Result<VehicleMessage> reply = rig.call(std::move(request));
    Clock::time_point end = Clock::now();
    if (!reply) {
      st.SkipWithError(reply.error().message.c_str());
      break;
    }
    us.push_back(std::chrono::duration<double, std::micro>(end - start).count());
  }
  std::sort(us.begin(), us.end());
  st.counters["p50_us"] = quantile(us, 0.50);
  st.counters["p90_us"] = quantile(us, 0.90);
  st.counters["p99_us"] = quantile(us, 0.99);
  st.counters["max_us"] = us.empty() ? 0.0 : us.back();
  st.SetItemsProcessed(static_cast<std::int64_t>(us.size()));
}

protocol::Request ping() { return protocol::make_ping(0); }
protocol::Request ask() { return protocol::make_ask(0, "depth_filter_off"); }

// Figure 10 up to the poll: network, setpoint, filter, submerge, timer.
// Returns the sim time of the last reply, or sets problem.
double dive(Rig& rig, std::string& problem) {
  using protocol::Value;
  struct Step {
    protocol::Request request;
    bool must_be_true;
  };
  const Step steps[] = {
      {protocol::make_ood(0, "start_network"), true},
      {protocol::make_exec(0, "setpoint", {Value::real(kSetpointDepthM), Value::real(kSetpointTimeoutS)}), true},
      {protocol::make_ask(0, "depth_filter_off"), true},
      {protocol::make_exec(0, "start_depth_filter"), true},
      {protocol::make_exec(0, "sleep", {Value::integer(1)}), true},
      {protocol::make_exec(0, "submerge"), true},
      {protocol::make_exec(0, "start_timer"), true},
  };
  double sim_time_s = 0.0;
  for (const Step& s : steps) {
    Timed t = timed(rig.call(s.request));
    if (t.problem.empty() && s.must_be_true && !t.value) t.problem = "answered 0";
    if (!t.problem.empty()) {
      problem = fmt::format("{}: {}", describe(s.request), t.problem);
      return 0.0;
    }
    sim_time_s = t.sim_time_s;
  }
  return sim_time_s;
}

void bm_poll(benchmark::State& st, Wait wait, protocol::Value sleep_s) {
  Rig rig(wait);
  std::string problem = rig.problem();
  double start_sim_s = problem.empty() ? dive(rig, problem) : 0.0;
  if (!problem.empty()) {
    st.SkipWithError(problem.c_str());
    return;
  }
  const protocol::Request poll[] = {
      protocol::make_exec(0, "sleep", {sleep_s}),
      protocol::make_ask(0, "depth_reached"),
      protocol::make_ask(0, "time_out"),
      protocol::make_ask(0, "system_problem"),
  };
  double end_sim_s = start_sim_s;
  std::int64_t reached = 0;
  std::int64_t requests = 0;
  Clock::time_point start = Clock::now();
  for (auto _ : st) {
    for (const protocol::Request& r : poll) {
      Timed t = timed(rig.call(r));
      if (!t.problem.empty()) {
        problem = fmt::format("{}: {}", describe(r), t.problem);
        break;
      }
      ++requests;
      end_sim_s = t.sim_time_s;
      if (&r == &poll[1] && t.value) ++reached;
    }
    if (!problem.empty()) {
      st.SkipWithError(problem.c_str());
      break;
    }
  }
  double wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  double sim_s = end_sim_s - start_sim_s;
  st.counters["sim_s"] = sim_s;
  st.counters["sim_s_per_wall_s"] = wall_s > 0 ? sim_s / wall_s : 0.0;
  // Polls that found the setpoint reached: shows the dive did happen.
  st.counters["reached_polls"] = static_cast<double>(reached);
  st.SetItemsProcessed(requests);
}

void register_all() {
  using protocol::Value;
  auto fixed = [](benchmark::internal::Benchmark* b, benchmark::IterationCount n) {
    b->Iterations(n)->UseRealTime()->Unit(benchmark::kMicrosecond);
  };
  fixed(benchmark::RegisterBenchmark("link/round_trip/ping",
                                     [](benchmark::State& st) { bm_round_trip(st, Wait::kBlock, ping); }),
        kRoundTrips);
  fixed(benchmark::RegisterBenchmark("link/round_trip/ask",
                                     [](benchmark::State& st) { bm_round_trip(st, Wait::kBlock, ask); }),
        kRoundTrips);
  fixed(benchmark::RegisterBenchmark("link/round_trip/ask_spinning",
                                     [](benchmark::State& st) { bm_round_trip(st, Wait::kSpin, ask); }),
        kRoundTrips);
  fixed(benchmark::RegisterBenchmark("link/poll/sleep_1",
                                     [](benchmark::State& st) { bm_poll(st, Wait::kBlock, Value::integer(1)); }),
        kPolls);
  fixed(benchmark::RegisterBenchmark("link/poll/sleep_0.1",
                                     [](benchmark::State& st) { bm_poll(st, Wait::kBlock, Value::real(0.1)); }),
        kPolls);
  fixed(benchmark::RegisterBenchmark("link/poll/sleep_0.1_spinning",
                                     [](benchmark::State& st) { bm_poll(st, Wait::kSpin, Value::real(0.1)); }),
        kPolls);
}

}  // namespace
}  // namespace strata::tactical

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  strata::tactical::register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
