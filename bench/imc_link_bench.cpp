// The IMC link's own latency (issue 35's target: <= 1 ms p99 on loopback
// between a vehicle state arriving and the ask it answers being replied to).
//
// A scripted IMC vehicle on its own thread (as a vehicle is its own process)
// and the Tactical level's tactical::ImcLink on the benchmark thread's
// io_context, over loopback UDP. One iteration: the link is sent `ask
// depth_reached` (answered at the vehicle's next EstimatedState, as every
// call over IMC is); the vehicle thread is woken, takes the time, and sends
// that EstimatedState; the reply handler takes the time again. Counters:
// p50_us, p99_us, max_us of (reply - state sent), over kTimed iterations.
//
//   imc_link/state_to_reply          the state alone
//   imc_link/state_to_reply_dune_mix the state behind the 16 packets a DUNE
//                                    vehicle sends per EstimatedState that a
//                                    controller does not read (ServoPosition,
//                                    EulerAngles, EntityState...: about 800/s
//                                    against EstimatedState's ~2/s, here 16
//                                    per state), filtered at their headers
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include <asio.hpp>

#include "imc/codec.h"
#include "tactical/imc_link.h"

namespace {

using namespace strata;
using Clock = std::chrono::steady_clock;
constexpr int kTimed = 2000;
constexpr double kEpoch = 1.7e9;

std::vector<std::uint8_t> packet(imc::Message m, double t) {
  imc::Packet p;
  p.header.timestamp = kEpoch + t;
  p.header.src = 0x00D1;
  p.message = std::move(m);
  return imc::encode(p).value();
}

std::vector<std::uint8_t> state_packet(double t) {
  imc::EstimatedState es;
  es.lat = 0.7188;
  es.lon = -0.1519;
  es.depth = 1.0f;
  return packet(es, t);
}

// Runs io until pred() or 5 s; false on the bound (the benchmark then skips).
template <typename Pred>
bool run_until(asio::io_context& io, Pred pred) {
  const auto deadline = Clock::now() + std::chrono::seconds(5);
  io.restart();
  while (!pred() && Clock::now() < deadline) io.run_one_for(std::chrono::milliseconds(10));
  return pred();
}

void state_to_reply(benchmark::State& bench, int noise_per_state) {
  asio::io_context io;
  asio::io_context vehicle_io;
  asio::ip::udp::socket vehicle(vehicle_io, asio::ip::udp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  tactical::ImcLinkOptions o;
  o.port = vehicle.local_endpoint().port();
  auto link = tactical::ImcLink::create(io, o);
  std::optional<core::Result<tactical::ImcVehicleInfo>> connected;
  link->connect([&](core::Result<tactical::ImcVehicleInfo> r) { connected = std::move(r); });

  // The handshake, by hand: read until the link's plan start, answer it.
  std::vector<std::uint8_t> buffer(65536);
  asio::ip::udp::endpoint peer;
  double t = 0.1;
  auto read_one = [&]() -> std::optional<imc::Packet> {
    if (!run_until(io, [&] { return vehicle.available() > 0; })) return std::nullopt;
    const std::size_t n = vehicle.receive_from(asio::buffer(buffer), peer);
    auto d = imc::decode(std::span<const std::uint8_t>(buffer.data(), n));
    if (auto* p = std::get_if<imc::Packet>(&d)) return *p;
    return std::nullopt;
  };
  if (!read_one()) return bench.SkipWithError("no Announce from the link");
  imc::Announce a;
  a.sys_name = "bench-vehicle";
  vehicle.send_to(asio::buffer(packet(a, t)), peer);
  vehicle.send_to(asio::buffer(state_packet(t)), peer);
  std::optional<imc::PlanControl> start;
  for (int i = 0; i < 20 && !start; ++i) {
    auto p = read_one();
    if (p) {
      if (auto* pc = std::get_if<imc::PlanControl>(&p->message)) start = *pc;
    }
  }
  if (!start) return bench.SkipWithError("no plan start from the link");
  imc::PlanControl ok;
  ok.type = imc::PlanControl::kSuccess;
  ok.request_id = start->request_id;
  ok.plan_id = start->plan_id;
  vehicle.send_to(asio::buffer(packet(ok, t)), peer);
  if (!run_until(io, [&] { return connected.has_value(); }) || !connected->ok()) {
    return bench.SkipWithError("the link did not connect");
  }

  // The vehicle's thread: on each wake-up, the time, then its packets.
  std::vector<std::vector<std::uint8_t>> noise;
  for (int i = 0; i < noise_per_state; ++i) {
    imc::EntityState es;  // one of the ~40 kinds a controller does not read
    es.description = "Servo Controller";
    noise.push_back(packet(es, t));
  }
  std::mutex m;
  std::condition_variable cv;
  int requested = 0;
  bool stop = false;
  std::atomic<std::int64_t> sent_at{0};
  std::thread vehicle_thread([&] {
    double vt = t;
    int served = 0;
    std::vector<std::uint8_t> drain(65536);
    for (;;) {
      {
        std::unique_lock lock(m);
        cv.wait(lock, [&] { return stop || requested > served; });
        if (stop) return;
        ++served;
      }
      asio::error_code ignored;
      while (vehicle.available(ignored) > 0) vehicle.receive(asio::buffer(drain), 0, ignored);  // References
      for (const auto& n : noise) vehicle.send_to(asio::buffer(n), peer, 0, ignored);
      vt += 0.1;
      auto state = state_packet(vt);
      sent_at = Clock::now().time_since_epoch().count();
      vehicle.send_to(asio::buffer(state), peer, 0, ignored);
    }
  });

  std::vector<double> us;
  us.reserve(kTimed);
  int iterations = 0;
  for (auto _ : bench) {
    for (int i = 0; i < kTimed; ++i) {
      std::optional<std::int64_t> replied;
      link->send(protocol::make_ask(0, "depth_reached"),
                 [&](core::Result<protocol::VehicleMessage>) { replied = Clock::now().time_since_epoch().count(); });
      {
        std::lock_guard lock(m);
        ++requested;
      }
      cv.notify_one();
      if (!run_until(io, [&] { return replied.has_value(); })) {
        bench.SkipWithError("no reply");
        break;
      }
      us.push_back(static_cast<double>(*replied - sent_at.load()) / 1000.0);
      ++iterations;
    }
  }
  {
    std::lock_guard lock(m);
    stop = true;
  }
  cv.notify_one();
  vehicle_thread.join();
  link->close();
  if (us.empty()) return;
  std::sort(us.begin(), us.end());
  auto at = [&](double q) {
    return us[std::min(us.size() - 1, static_cast<std::size_t>(q * static_cast<double>(us.size())))];
  };
  bench.counters["p50_us"] = at(0.5);
  bench.counters["p99_us"] = at(0.99);
  bench.counters["max_us"] = us.back();
  bench.SetItemsProcessed(iterations);
}

void BM_StateToReply(benchmark::State& s) { state_to_reply(s, 0); }
void BM_StateToReplyDuneMix(benchmark::State& s) { state_to_reply(s, 16); }

BENCHMARK(BM_StateToReply)->Name("imc_link/state_to_reply")->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StateToReplyDuneMix)
    ->Name("imc_link/state_to_reply_dune_mix")
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
