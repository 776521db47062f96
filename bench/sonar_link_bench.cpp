// The sonar beside the control link (issue 8), on the wall clock at 10x real
// time as a watched run goes: the vehicle server (sonar search's nominal
// scenario, target present) on its own thread, the Tactical level's
// VehicleLink on the benchmark thread, and the Sonar Manager
// (sonar::run_sonar_manager, the code of `strata sonar`, here on a thread of
// this process) reading the sonar socket and writing its scans to a temporary
// folder.
//
//   sonar/link_rtt   `ping` round trips on the control link, one every 2 ms,
//                    in blocks of 250 with the sonar alternately off and on
//                    (`exec stop_sonar` / `exec start_sonar` between blocks),
//                    so both see the same machine. Counters: p50/p99 of each
//                    (us) and their ratios on/off. Target: on within 10%.
//   The manager's side, after the last block: pings the vehicle made
//   (vehicle_pings), pings the manager read (manager_pings), and what was
//   lost: seq gaps, pings the vehicle dropped for a slow reader, pings the
//   manager's queue dropped. Target: none lost at 10x real time.
#include <benchmark/benchmark.h>

#include <stdlib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>
#include <thread>
#include <vector>

#include <asio.hpp>

#include "protocol/codec.h"
#include "sonar/manager.h"
#include "tactical/vehicle_link.h"
#include "vehicle/params.h"
#include "vehicle/scenario.h"
#include "vehicle/server.h"
#include "vehicle/simulation.h"

namespace strata {
namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::clamp<std::size_t>(rank, 1, v.size()) - 1];
}

void bm_link_rtt(benchmark::State& st) {
  auto scenario =
      vehicle::load_scenario(std::string(STRATA_SOURCE_DIR) + "/missions/sonar_search/scenarios/nominal.toml");
  if (!scenario) {
    st.SkipWithError(scenario.error().message.c_str());
    return;
  }
  vehicle::Simulation sim(vehicle::default_params(), scenario.value());
  asio::io_context vehicle_io;
  auto work = asio::make_work_guard(vehicle_io);
  vehicle::ServerOptions so;
  so.clock = protocol::ClockMode::Wall;
  so.speed = 10.0;
  vehicle::VehicleServer server(vehicle_io, sim, so);
  if (auto r = server.start(); !r) {
    st.SkipWithError(r.error().message.c_str());
    return;
  }
  const std::uint16_t sonar_port = server.sonar_port();
  std::thread vehicle_thread([&] { vehicle_io.run(); });

  std::string pattern = (fs::temp_directory_path() / "strata_sonar_link_XXXXXX").string();
  const fs::path out = ::mkdtemp(pattern.data()) ? fs::path(pattern) : fs::path();
  sonar::ManagerOptions mo;
  mo.capture.port = sonar_port;
  mo.out_dir = out;
  mo.log = [](const std::string&) {};
  sonar::ManagerSummary summary;
  std::jthread manager([&](std::stop_token stop) { summary = sonar::run_sonar_manager(mo, stop); });

  asio::io_context io;
  tactical::LinkOptions lo;
  lo.port = server.port();
  auto link = tactical::VehicleLink::create(io, lo);
  std::optional<core::Result<protocol::Welcome>> welcome;
  link->connect([&](core::Result<protocol::Welcome> w) { welcome = std::move(w); });
  while (!welcome && io.run_one() > 0) {}
  std::string problem = !welcome ? "no hello" : !welcome->ok() ? welcome->error().message : "";
  auto call = [&](protocol::Request r) -> bool {
    std::optional<core::Result<protocol::VehicleMessage>> reply;
    link->send(std::move(r), [&](core::Result<protocol::VehicleMessage> m) { reply = std::move(m); });
    while (!reply && io.run_one() > 0) {}
    if (!reply || !reply->ok()) {
      problem = reply ? reply->error().message : "the link's loop ran out of work";
      return false;
    }
    return true;
  };
  if (problem.empty()) call(protocol::make_ood(0, "start_network", {}));

  std::vector<double> rtt[2];
  bool on = false;
  int in_block = 0;
  for (auto _ : st) {
    if (!problem.empty()) break;
    if (in_block == 250) {
      st.PauseTiming();
      on = !on;
      call(protocol::make_exec(0, on ? "start_sonar" : "stop_sonar", {}));
      in_block = 0;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      st.ResumeTiming();
    }
    const auto t0 = Clock::now();
    if (!call(protocol::make_ping(0))) break;
    rtt[on].push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    ++in_block;
    st.PauseTiming();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    st.ResumeTiming();
  }
  if (problem.empty() && on) call(protocol::make_exec(0, "stop_sonar", {}));
  link->close();
  io.poll();
  // The vehicle stops: the manager gets the end frame and finishes.
  std::uint32_t vehicle_pings = 0;
  std::uint64_t vehicle_dropped = 0;
  asio::post(vehicle_io, [&] {
    vehicle_pings = server.sonar() ? server.sonar()->pings() : 0;
    vehicle_dropped = server.sonar() ? server.sonar()->dropped() : 0;
    server.stop();
  });
  manager.join();
  work.reset();
  vehicle_thread.join();
  std::error_code ec;
  fs::remove_all(out, ec);
  if (!problem.empty()) {
    st.SkipWithError(problem.c_str());
    return;
  }
  const double off50 = quantile(rtt[0], 0.5), on50 = quantile(rtt[1], 0.5);
  const double off99 = quantile(rtt[0], 0.99), on99 = quantile(rtt[1], 0.99);
  st.counters["off_p50_us"] = off50;
  st.counters["on_p50_us"] = on50;
  st.counters["off_p99_us"] = off99;
  st.counters["on_p99_us"] = on99;
  st.counters["p50_on/off"] = off50 > 0 ? on50 / off50 : 0;
  st.counters["p99_on/off"] = off99 > 0 ? on99 / off99 : 0;
  st.counters["vehicle_pings"] = vehicle_pings;
  st.counters["manager_pings"] = static_cast<double>(summary.capture.pings);
  st.counters["lost"] = static_cast<double>(summary.capture.lost_pings + vehicle_dropped + summary.capture.queue_drops);
  st.counters["frames"] = static_cast<double>(summary.frames);
}

BENCHMARK(bm_link_rtt)->Name("sonar/link_rtt")->Iterations(5000)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace
}  // namespace strata

BENCHMARK_MAIN();
