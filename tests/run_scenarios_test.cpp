// `strata run` of the tank mission, in-process (cli::run_mission), for every
// shipped scenario: the phases and how they end, the primitive calls in the
// order the nets make them, the vehicle's final state, and the mission log
// that records it all. Helpers and bounds: support/tank_run.h.
#include "support/tank_run.h"

#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace strata::cli::run_testing {
namespace {

// What holds for every run of a valid mission on the embedded vehicle: the
// log is well formed, agrees with the RunReport and the console summary, and
// ends with the vehicle's final state.
void expect_consistent(const MissionRun& r, const std::string& scenario) {
  const ParsedLog& log = r.log;
  ASSERT_FALSE(log.lines.empty());
  EXPECT_EQ("", r.err) << "a valid mission writes nothing to err";
  ASSERT_TRUE(r.report.result.has_value()) << r.out << r.err;

  const json& header = log.lines.front();
  EXPECT_EQ("run", header["event"]);
  EXPECT_EQ(scenario, header["scenario"]);
  EXPECT_EQ("lockstep", header["clock"]);

  double last = 0;
  for (std::size_t i = 0; i < log.lines.size(); ++i) {
    if (!log.lines[i].contains("sim_time")) continue;
    double t = log.lines[i]["sim_time"];
    EXPECT_GE(t, last - kEps) << "sim_time goes back at line " << i + 1 << ": " << log.lines[i].dump();
    last = std::max(last, t);
  }
  for (const auto& c : log.calls) {
    EXPECT_TRUE(c.result.has_value()) << "request " << c.id << " (" << c.primitive << ") has no reply line";
    if (!c.result) continue;
    EXPECT_GT(c.reply_line, c.request_line);
    EXPECT_GE(c.replied_s, c.requested_s - kEps);
  }
  // Every call the Tactical level made: to the vehicle (request lines) or REPORTs.
  EXPECT_EQ(r.report.primitive_calls, log.calls.size() + log.report_lines.size());

  EXPECT_EQ(r.report.phases, log.phases());
  ASSERT_TRUE(log.mission_end.has_value());
  const json& end = log.at(log.mission_end);
  const auto& result = *r.report.result;
  EXPECT_EQ(std::string(strategic::to_string(result.outcome)), end["outcome"]);
  EXPECT_EQ(result.exit, end["exit"]);
  EXPECT_EQ(result.reason, end["reason"]);
  EXPECT_EQ(result.outcome == Outcome::Completed ? 0 : 1, r.report.exit_code);

  ASSERT_TRUE(log.vehicle_final.has_value());
  EXPECT_EQ(log.lines.size() - 1, *log.mission_end)
      << "mission_end is the last line: the run wrote it after its safe end";
  EXPECT_EQ(*log.mission_end - 1, *log.vehicle_final) << "vehicle_final comes just before it";
  EXPECT_EQ(r.report.exit_code, end["exit_code"]);
  EXPECT_NEAR(result.sim_time_s, end["mission_sim_time"].get<double>(), kEps);
  const json& final_line = log.at(log.vehicle_final);
  ASSERT_TRUE(r.report.final_depth_m.has_value());
  EXPECT_NEAR(*r.report.final_depth_m, final_line["depth_m"].get<double>(), kEps);
  EXPECT_EQ(r.report.vehicle_watchdog_tripped, final_line["watchdog_tripped"].get<bool>());
  EXPECT_GE(final_line["sim_time"].get<double>(), result.sim_time_s - kEps);

  EXPECT_NE(std::string::npos, r.out.find("log: " + r.log_path + " (" + std::to_string(log.lines.size()) + " lines)"))
      << r.out;

  // The OOD opens the network first and the last request shuts it down.
  ASSERT_FALSE(log.calls.empty());
  EXPECT_EQ("start_network", log.calls.front().primitive);
  EXPECT_EQ("initialize", log.calls.front().phase);
  EXPECT_TRUE(log.calls.front().answered(1));
  EXPECT_EQ("shutdown_network", log.calls.back().primitive);
  EXPECT_EQ("", log.calls.back().phase) << "the mission net's own OOD call";
  EXPECT_EQ(1u, log.count([](const Call& c) { return c.primitive == "shutdown_network"; }));
  ASSERT_FALSE(log.phase_ends.empty());
  EXPECT_GT(log.calls.back().request_line, log.phase_ends.back().line) << "shutdown_network after every phase";
  if (!log.emergency) {
    EXPECT_LT(log.calls.back().reply_line, *log.mission_end) << "the mission's own call";
  }
}

// The mission's own abort path (paper Figure 10): `trigger` answered 1 in
// `phase`, the phase surfaces at once, asks surface_reached until it answers
// 1, and aborts; the mission REPORTs and shuts the network down.
void expect_abort_path(const MissionRun& r, const std::string& phase, const std::string& trigger) {
  const ParsedLog& log = r.log;
  ASSERT_TRUE(r.report.result.has_value());
  EXPECT_EQ(Outcome::Aborted, r.report.result->outcome);
  EXPECT_EQ("closed_after_abort", r.report.result->exit) << "tank.coral's second exit";
  EXPECT_EQ(1, r.report.exit_code);
  EXPECT_FALSE(r.report.emergency_shutdown) << "the mission ran its own abort path";
  EXPECT_FALSE(log.emergency.has_value());
  EXPECT_FALSE(r.report.vehicle_watchdog_tripped);
  EXPECT_TRUE(std::all_of(log.calls.begin(), log.calls.end(), [](const Call& c) { return !c.failed(); }));

  std::vector<const Call*> calls = log.in_phase(phase);
  auto trig = std::find_if(calls.begin(), calls.end(), [&](const Call* c) { return c->is(trigger, 1); });
  ASSERT_TRUE(trig != calls.end()) << trigger << " never answered 1 in " << phase;
  auto next = trig + 1;
  ASSERT_TRUE(next != calls.end()) << "nothing after " << trigger << " answered 1";
  EXPECT_EQ("surface", (*next)->primitive) << "the phase surfaces right after " << trigger;
  EXPECT_TRUE((*next)->answered(1));
  const Call* surfaced = nullptr;
  for (auto it = next + 1; it != calls.end(); ++it) {
    EXPECT_EQ("surface_reached", (*it)->primitive) << "only surface_reached after surface";
    EXPECT_EQ(nullptr, surfaced) << "asked again after surface_reached answered 1";
    if ((*it)->answered(1)) surfaced = *it;
  }
  ASSERT_NE(nullptr, surfaced) << "surface_reached never answered 1 in " << phase;

  ASSERT_FALSE(log.phase_ends.empty());
  const PhaseEndLine& end = log.phase_ends.back();
  EXPECT_EQ(phase, end.net);
  EXPECT_EQ("aborted", end.result);
  EXPECT_GT(end.line, surfaced->reply_line);
  ASSERT_EQ(1u, log.report_lines.size());
  const json& report = log.lines[log.report_lines.front()];
  EXPECT_EQ("mission aborted: shutting down the vehicle network", report["text"]);
  EXPECT_GT(log.report_lines.front(), end.line);
  const Call& shutdown = log.calls.back();
  EXPECT_GT(shutdown.request_line, log.report_lines.front());
  EXPECT_TRUE(shutdown.answered(1));
  EXPECT_GT(*log.mission_end, shutdown.reply_line);
  EXPECT_EQ(1u, log.count([](const Call& c) { return c.primitive == "surface"; }));

  ASSERT_TRUE(r.report.final_depth_m.has_value());
  EXPECT_LE(*r.report.final_depth_m, kParams.surface_depth_m) << "the vehicle ends at the surface";
  EXPECT_NE(std::string::npos, r.out.find("mission tank: aborted (exit closed_after_abort)")) << r.out;
}

// A leak at the scenario's time is seen at the next system_problem check of
// `phase` (within one monitoring cycle), never before it.
void expect_leak_seen_in_time(const MissionRun& r, const std::string& scenario, const std::string& phase) {
  const double leak_s = fault_of(scenario, vehicle::FaultKind::Leak).at_s;
  const ParsedLog& log = r.log;
  for (const auto& c : log.calls) {
    if (c.primitive == "system_problem" && c.replied_s < leak_s - kEps) {
      EXPECT_TRUE(c.answered(0)) << "system_problem answered " << c.result->dump() << " at " << c.replied_s
                                 << " s, before the leak at " << leak_s << " s";
    }
  }
  const Call* first_after =
      log.first([&](const Call& c) { return c.primitive == "system_problem" && c.requested_s >= leak_s - kEps; });
  ASSERT_NE(nullptr, first_after) << "no system_problem check after the leak at " << leak_s << " s";
  EXPECT_TRUE(first_after->answered(1)) << "the first check after the leak missed it";
  EXPECT_EQ(phase, first_after->phase);
  EXPECT_LE(first_after->requested_s, leak_s + kMonitoringCycleS + kEps);
  ASSERT_FALSE(log.phase_ends.empty());
  EXPECT_GT(log.phase_ends.back().sim_time_s, leak_s);
  EXPECT_EQ(0u, log.count([](const Call& c) { return c.is("time_out", 1); }));
}

// ---- the scenarios ----------------------------------------------------------

TEST(TankScenario, NominalCompletesAllFourPhases) {
  const MissionRun& r = scenario_run("nominal");
  expect_consistent(r, "nominal");
  const ParsedLog& log = r.log;
  EXPECT_EQ((std::vector<std::string>{"initialize completed", "dive_from_surface completed",
                                      "submerge_to_depth completed", "return_to_surface completed"}),
            r.report.phases);
  ASSERT_TRUE(r.report.result.has_value());
  EXPECT_EQ(Outcome::Completed, r.report.result->outcome);
  EXPECT_EQ("closed", r.report.result->exit);
  EXPECT_EQ("", r.report.result->reason);
  EXPECT_EQ(0, r.report.exit_code);
  EXPECT_NE(std::string::npos, r.out.find("mission tank: completed (exit closed)")) << r.out;

  // One setpoint read per phase 2, 3, 4, in the order of the data file.
  const auto data = setpoints();
  std::vector<std::string> setpoint_phases;
  for (const auto& c : log.calls) {
    if (c.primitive != "next_setpt_data") continue;
    EXPECT_TRUE(c.answered(1));
    setpoint_phases.push_back(c.phase);
  }
  EXPECT_EQ(data.size(), setpoint_phases.size());
  EXPECT_EQ((std::vector<std::string>{"dive_from_surface", "submerge_to_depth", "return_to_surface"}), setpoint_phases);

  // The key calls, in this order (other calls may come between them).
  const std::vector<std::pair<std::string, int>> key = {{"start_network", 1},   {"next_setpt_data", 1}, {"submerge", 1},
                                                        {"depth_reached", 1},   {"next_setpt_data", 1}, {"submerge", 1},
                                                        {"depth_reached", 1},   {"next_setpt_data", 1}, {"surface", 1},
                                                        {"surface_reached", 1}, {"shutdown_network", 1}};
  std::size_t k = 0;
  for (const auto& c : log.calls) {
    if (k < key.size() && c.is(key[k].first, key[k].second)) ++k;
  }
  EXPECT_EQ(key.size(), k) << "missing or out of order: " << (k < key.size() ? key[k].first : "");

  // Each dive ends on its first "depth reached"; nothing went wrong on the way.
  for (const std::string phase : {"dive_from_surface", "submerge_to_depth"}) {
    auto calls = log.in_phase(phase);
    ASSERT_FALSE(calls.empty()) << phase;
    EXPECT_TRUE(calls.back()->is("depth_reached", 1)) << phase << " ended on " << calls.back()->primitive;
    EXPECT_EQ(1, std::count_if(calls.begin(), calls.end(), [](const Call* c) { return c->is("depth_reached", 1); }));
  }
  EXPECT_TRUE(log.in_phase("return_to_surface").back()->is("surface_reached", 1));
  for (const auto& c : log.calls) {
    EXPECT_FALSE(c.failed()) << c.primitive << ": " << c.result->dump();
    EXPECT_FALSE(c.is("time_out", 1) || c.is("system_problem", 1)) << c.primitive << " at " << c.replied_s;
  }
  EXPECT_TRUE(log.report_lines.empty());
  EXPECT_FALSE(log.emergency.has_value());
  EXPECT_FALSE(r.report.emergency_shutdown);

  // The vehicle went down past the first setpoint and came back up.
  ASSERT_FALSE(log.telemetry_depths_m.empty());
  EXPECT_GT(*std::max_element(log.telemetry_depths_m.begin(), log.telemetry_depths_m.end()), data.at(0).depth_m);
  ASSERT_TRUE(r.report.final_depth_m.has_value());
  EXPECT_LE(*r.report.final_depth_m, kParams.surface_depth_m);
  EXPECT_FALSE(r.report.vehicle_watchdog_tripped);
}

TEST(TankScenario, WeakThrustersTimeOutInPhase2AndAbort) {
  const MissionRun& r = scenario_run("weak_thrusters");
  expect_consistent(r, "weak_thrusters");
  EXPECT_EQ((std::vector<std::string>{"initialize completed", "dive_from_surface aborted"}), r.report.phases);
  expect_abort_path(r, "dive_from_surface", "time_out");
  const ParsedLog& log = r.log;

  // time_out says yes once the setpoint's time limit has passed since
  // start_timer, at the first check after it (one monitoring cycle at most).
  const double limit_s = setpoints().at(0).timeout_s;
  const Call* timer = log.first([](const Call& c) { return c.primitive == "start_timer"; });
  const Call* out = log.first([](const Call& c) { return c.is("time_out", 1); });
  ASSERT_NE(nullptr, timer);
  ASSERT_NE(nullptr, out);
  EXPECT_EQ("dive_from_surface", timer->phase);
  EXPECT_GE(out->requested_s - timer->requested_s, limit_s - kEps);
  EXPECT_LE(out->requested_s - timer->replied_s, limit_s + kMonitoringCycleS + kEps);
  for (const auto& c : log.calls) {
    if (c.primitive == "time_out" && c.requested_s - timer->replied_s < limit_s - kEps) {
      EXPECT_TRUE(c.answered(0)) << "time_out answered yes early, at " << c.requested_s << " s";
    }
  }
  EXPECT_EQ(0u, log.count([](const Call& c) { return c.is("depth_reached", 1); }));
  EXPECT_EQ(0u, log.count([](const Call& c) { return c.is("system_problem", 1); }));
  // 10% thrust cannot beat the buoyancy: the vehicle never leaves the surface.
  ASSERT_FALSE(log.telemetry_depths_m.empty());
  EXPECT_LE(*std::max_element(log.telemetry_depths_m.begin(), log.telemetry_depths_m.end()), kParams.surface_depth_m);
}

TEST(TankScenario, LeakInPhase2SurfacesAndAborts) {
  const MissionRun& r = scenario_run("leak_phase2");
  expect_consistent(r, "leak_phase2");
  EXPECT_EQ((std::vector<std::string>{"initialize completed", "dive_from_surface aborted"}), r.report.phases);
  expect_abort_path(r, "dive_from_surface", "system_problem");
  expect_leak_seen_in_time(r, "leak_phase2", "dive_from_surface");
  EXPECT_EQ(0u, r.log.count([](const Call& c) { return c.is("depth_reached", 1); }))
      << "the leak comes before the first setpoint is reached";
}

TEST(TankScenario, LeakInPhase3SurfacesAndAborts) {
  const MissionRun& r = scenario_run("leak_phase3");
  expect_consistent(r, "leak_phase3");
  EXPECT_EQ(
      (std::vector<std::string>{"initialize completed", "dive_from_surface completed", "submerge_to_depth aborted"}),
      r.report.phases);
  expect_abort_path(r, "submerge_to_depth", "system_problem");
  expect_leak_seen_in_time(r, "leak_phase3", "submerge_to_depth");
  auto phase2 = r.log.in_phase("dive_from_surface");
  ASSERT_FALSE(phase2.empty());
  EXPECT_TRUE(phase2.back()->is("depth_reached", 1));
  EXPECT_LT(phase2.back()->replied_s, fault_of("leak_phase3", vehicle::FaultKind::Leak).at_s);
  EXPECT_EQ(1u, r.log.count([](const Call& c) { return c.is("depth_reached", 1); }));
}

TEST(TankScenario, LinkLossFailsAndTheVehicleSurfacesByItsWatchdog) {
  const MissionRun& r = scenario_run("link_loss");
  expect_consistent(r, "link_loss");
  const ParsedLog& log = r.log;
  const vehicle::Fault loss = fault_of("link_loss", vehicle::FaultKind::LinkLoss);
  EXPECT_FALSE(loss.duration_s.has_value()) << "lost for good";

  ASSERT_TRUE(r.report.result.has_value());
  const auto& result = *r.report.result;
  EXPECT_EQ(Outcome::Failed, result.outcome);
  EXPECT_EQ("", result.exit);
  EXPECT_EQ(1, r.report.exit_code);
  ASSERT_TRUE(result.call_error.has_value());
  EXPECT_TRUE(*result.call_error == tactical::CallError::Kind::TimedOut ||
              *result.call_error == tactical::CallError::Kind::LinkLost)
      << "TimedOut or LinkLost: the link to the vehicle is gone";
  EXPECT_NE(std::string::npos, result.reason.find("no reply")) << result.reason;
  EXPECT_NE(std::string::npos, r.out.find("mission tank: failed: lost the link to the vehicle")) << r.out;
  EXPECT_EQ((std::vector<std::string>{"initialize completed", "dive_from_surface cancelled"}), r.report.phases);

  // The vehicle answered nothing after the link went; the call in flight then failed.
  const Call* first_failed = log.first([](const Call& c) { return c.failed(); });
  ASSERT_NE(nullptr, first_failed);
  EXPECT_EQ("dive_from_surface", first_failed->phase);
  EXPECT_LE(first_failed->requested_s, loss.at_s + kEps);
  for (const auto& c : log.calls) {
    if (!c.failed()) {
      EXPECT_LE(c.replied_s, loss.at_s + kEps) << c.primitive << " answered after the loss";
    }
  }
  EXPECT_TRUE(log.report_lines.empty()) << "the mission's abort path never ran";
  EXPECT_EQ(0u, log.count([](const Call& c) { return c.primitive == "surface"; }));

  // The runner sent Figure 10's `done` itself, and nobody answered.
  EXPECT_TRUE(r.report.emergency_shutdown);
  ASSERT_TRUE(log.emergency.has_value());
  EXPECT_EQ("ood shutdown_network", log.at(log.emergency)["action"]);
  EXPECT_LT(*log.emergency, *log.mission_end) << "the safe end runs before the log is closed";
  const Call& shutdown = log.calls.back();
  EXPECT_EQ("shutdown_network", shutdown.primitive);
  EXPECT_GT(shutdown.request_line, *log.emergency);
  EXPECT_TRUE(shutdown.failed()) << "a lost link answers nothing";
  EXPECT_NE(std::string::npos, r.out.find("after it: ood shutdown_network sent by strata run, unanswered (")) << r.out;

  // The vehicle's watchdog surfaced it after watchdog_s of silence.
  EXPECT_TRUE(r.report.vehicle_watchdog_tripped);
  ASSERT_TRUE(r.report.final_depth_m.has_value());
  EXPECT_LE(*r.report.final_depth_m, kParams.surface_depth_m);
  EXPECT_GE(log.at(log.vehicle_final)["sim_time"].get<double>(), loss.at_s + kParams.watchdog_s - kEps);
  EXPECT_NE(std::string::npos, r.out.find("surfaced by its own watchdog")) << r.out;
}

// Regression: in lockstep the reply timeouts were wall-clock, so every run
// with a lost link waited about 2 s of wall time doing nothing (48 of the
// tank campaign's 55 s) and logged each timeout at its request's time. Now
// the vehicle's clock goes on through the silence (a bounded `advance`) and
// a call times out its catalogue timeout_s later, in simulated time.
TEST(TankScenario, ALostLinkInLockstepTimesCallsOutInSimulatedTime) {
  const MissionRun& r = scenario_run("link_loss");
  const ParsedLog& log = r.log;
  const vehicle::Fault loss = fault_of("link_loss", vehicle::FaultKind::LinkLoss);
  const Call* first_failed = log.first([](const Call& c) { return c.failed(); });
  ASSERT_NE(nullptr, first_failed);
  const std::string error = (*first_failed->result)["error"].get<std::string>();
  EXPECT_NE(std::string::npos, error.find("within 2 s of simulated time")) << error;
  EXPECT_NEAR(first_failed->requested_s + 2.0, first_failed->replied_s, kEps) << "timed out 2 simulated s later";
  EXPECT_GT(first_failed->replied_s, loss.at_s);
  // Each later call waits its own timeout in simulated time, one after the other.
  const Call& shutdown = log.calls.back();
  EXPECT_NEAR(shutdown.requested_s + 10.0, shutdown.replied_s, kEps) << "ood shutdown_network: timeout_s 10";
  // The vehicle's log says when it was up, though nobody heard its telemetry.
  const std::size_t up = r.out.find(" s: at the surface (link silent); holding");
  ASSERT_NE(std::string::npos, up) << r.out;
  const std::size_t line = r.out.rfind("vehicle: ", up);
  ASSERT_NE(std::string::npos, line) << r.out;
  const double up_s = std::strtod(r.out.c_str() + line + 9, nullptr);
  EXPECT_GT(up_s, loss.at_s + kParams.watchdog_s) << "after the watchdog's trip";
  EXPECT_LT(up_s, shutdown.replied_s) << "before the run gave up on the vehicle";
}

// Every phase_start has its phase_end (log_observer.h: "these replay a run's
// markings exactly"), also when the mission fails: regression test for the
// mission net being closed without a phase_end on a Failed run.
TEST(TankScenario, EveryPhaseStartHasAPhaseEndWhenTheMissionFails) {
  const MissionRun& r = scenario_run("link_loss");
  std::map<std::uint64_t, int> open;
  for (const auto& line : r.log.lines) {
    if (line["event"] == "phase_start") ++open[line["instance"].get<std::uint64_t>()];
    if (line["event"] == "phase_end") --open[line["instance"].get<std::uint64_t>()];
  }
  for (const auto& [instance, n] : open) EXPECT_EQ(0, n) << "instance " << instance;
}

}  // namespace
}  // namespace strata::cli::run_testing
