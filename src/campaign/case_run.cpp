#include "campaign/case_run.h"

#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "campaign/bound.h"
#include "core/file.h"
#include "run/observer.h"
#include "run/session.h"
#include "vehicle/params.h"

namespace strata::campaign {
namespace {

// The scenario's name as the run sees it: never a file on disk, it is read
// from memory through RunOptions::read_file.
constexpr const char* kScenarioName = "campaign-case.toml";
constexpr std::size_t kMaxMissionFileBytes = std::size_t{16} << 20;
constexpr std::uint64_t kMaxCaseLogBytes = std::uint64_t{64} << 20;

// Gathers what the expectations and the coverage need, as the run goes.
class CaseWatcher final : public run::RunObserver {
 public:
  CaseWatcher(std::optional<double> fault_at_s, double surface_depth_m, const coral::BoundQuery* bound)
      : fault_at_s_(fault_at_s), surface_depth_m_(surface_depth_m), bound_(bound) {}

  void telemetry(const protocol::Telemetry& t) override {
    if (!t.depth_m) return;  // a sensor dropout
    max_depth_m = std::max(max_depth_m.value_or(*t.depth_m), *t.depth_m);
    // At the surface as the vehicle judges it (surface_reached answers by
    // the depth filter's estimate), not by one noisy depth-cell reading: a
    // mission that surfaces and shuts down at once may end with the last
    // reading a few millimetres over surface_depth_m, the estimate under.
    const double judged = t.filtered_depth_m.value_or(*t.depth_m);
    if (fault_at_s_ && !surfaced_at_s && t.sim_time_s >= *fault_at_s_ - 1e-9 && judged <= surface_depth_m_) {
      surfaced_at_s = t.sim_time_s;
      if (bound_ && bound_->to == coral::BoundQuery::To::Surface) bound_to(t.sim_time_s);
    }
  }
  // The vehicle's own word that it reached the surface ("13.0 s: at the
  // surface; holding"): with the link gone, the run passes on the vehicle's
  // log lines from after it last heard from it as notes ("vehicle: ...").
  void vehicle_event(const std::string& text, double sim_time_s) override { surfaced_line(text, sim_time_s); }
  void note(const std::string& text, std::optional<double> sim_time_s) override {
    if (!text.starts_with("vehicle: ")) return;
    const char* start = text.c_str() + 9;
    char* end = nullptr;
    const double t = std::strtod(start, &end);
    if (end == start) return;
    surfaced_line(text, sim_time_s.value_or(t));
  }
  void fired(const strategic::Firing& f) override { fired_.insert(fmt::format("{}.{}", f.net, f.transition_name)); }
  void action_started(const strategic::ActionStart& a) override {
    if (a.is_call(core::CallVerb::Ask)) asks_[a.id] = std::string(a.primitive);
    if (bound_ && bound_->to == coral::BoundQuery::To::Call && a.verb && a.primitive == bound_->to_name &&
        (!bound_->to_verb || a.verb == bound_->to_verb)) {
      bound_to(a.sim_time_s);
    }
  }
  void action_finished(const strategic::ActionFinish& a) override {
    auto it = asks_.find(a.id);
    if (it == asks_.end()) return;
    answers_.insert(fmt::format("{}={}", it->second, a.value ? 1 : 0));
    asks_.erase(it);
  }
  void guard_tripped(const strategic::GuardTrip& e) override {
    guard_trips.emplace_back(std::string(e.guard), e.sim_time_s);
  }
  void phase_ended(const strategic::PhaseEnd& e) override {
    // PROLOG rules that simply finish name no exit place.
    if (!e.cancelled) exits_.insert(fmt::format("{}.{}", e.name, e.exit.empty() ? "(end)" : e.exit));
    // The mission's own end comes last: a phase's exit of the same name
    // before it is forgotten when the next phase ends.
    if (bound_ && bound_->to == coral::BoundQuery::To::Exit && !e.cancelled) {
      last_end_ = {e.exit == bound_->to_name, e.sim_time_s};
    }
  }
  // Once the run is over: the mission's exit, when the bound names one.
  void finish() {
    if (last_end_.first) bound_to(last_end_.second);
  }

  nlohmann::ordered_json coverage() const { return {{"fired", fired_}, {"answers", answers_}, {"exits", exits_}}; }

  std::optional<double> max_depth_m;
  std::vector<std::pair<std::string, double>> guard_trips;
  std::optional<double> surfaced_at_s;      // from telemetry
  std::optional<double> logged_surface_s;   // from the vehicle's log
  std::optional<double> bound_to_at_s;      // the bound's TO, first at or after the fault
  std::optional<double> bound_to_before_s;  // ... last before it

 private:
  void surfaced_line(const std::string& text, double t) {
    if (fault_at_s_ && !logged_surface_s && t >= *fault_at_s_ - 1e-9 &&
        text.find("at the surface") != std::string::npos) {
      logged_surface_s = t;
    }
  }

  void bound_to(double t) {
    if (!fault_at_s_ || bound_to_at_s) return;
    if (t + 1e-9 >= *fault_at_s_) {
      bound_to_at_s = t;
    } else {
      bound_to_before_s = t;
    }
  }

  std::optional<double> fault_at_s_;
  double surface_depth_m_;
  const coral::BoundQuery* bound_;
  std::pair<bool, double> last_end_{false, 0.0};
  std::set<std::string> fired_, answers_, exits_;
  std::map<strategic::ActionId, std::string> asks_;
};

// Written whole, never through a link (the folder was checked when made).
bool write_new_file(const std::string& path, const std::string& text) {
  return core::write_file_atomically(path, text).ok();
}

std::string shell_quote(const std::string& s) {
  if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_./-=:,+@%") ==
                        std::string::npos) {
    return s;
  }
  std::string out = "'";
  for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

// Times from the vehicle's clock, to the microsecond: 3.4, not 3.4000000000000004.
double tidy_s(double t) { return std::round(t * 1e6) / 1e6; }

// Why a case's run did not start, in the campaign's words: the input and
// the run's message, at most 500 bytes.
std::string not_started_reason(const run::RunReport& report) {
  if (!report.error) return "the run did not start";
  const run::Error& e = *report.error;
  std::string line = e.input.empty() ? e.message : e.input + ": " + e.message;
  if (line.size() > 500) line.resize(500);
  return line;
}

// An EXEC that the scripted answers failed while the vehicle carried it out.
struct ScriptedExecFailure {
  std::string primitive;
  std::string where;  // "answers[2], step 4"
  double sim_time_s = 0.0;
};

// From a mission log's scripted_answer records (docs/mission-log.md).
std::vector<ScriptedExecFailure> scripted_exec_failures(const std::string& log) {
  std::vector<ScriptedExecFailure> out;
  std::istringstream in(log);
  std::string line;
  while (std::getline(in, line)) {
    if (line.find("\"scripted_answer\"") == std::string::npos) continue;
    const auto j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object() || j.value("event", "") != "scripted_answer") continue;
    if (j.value("action", "") != "exec" || j.value("answer", 1) != 0 || j.value("vehicle", 0) != 1) continue;
    const auto step = j.value("step", 0);
    out.push_back({j.value("primitive", ""),
                   fmt::format("answers[{}]{}", j.value("answer_index", 0), step ? fmt::format(", step {}", step) : ""),
                   j.value("sim_time", 0.0)});
  }
  return out;
}

}  // namespace

bool refused_exec(const tactical::CallRecord& call) {
  if (call.verb != core::CallVerb::Exec) return false;
  if (call.error) return call.error->kind == tactical::CallError::Kind::Refused;
  return call.value == false;
}

namespace {

Observation observe(const run::RunReport& report, const CaseWatcher& watcher, const Case& c, double surface_depth_m,
                    const std::vector<ScriptedExecFailure>& scripted_failures) {
  Observation o;
  if (!report.result) {
    o.outcome = "error";
    o.reason = not_started_reason(report);
    return o;
  }
  const strategic::MissionResult& r = *report.result;
  o.outcome = std::string(strategic::to_string(r.outcome));
  o.reason = r.reason;
  o.stopped_by = report.stopped_by;
  o.stalled = r.stalled;
  o.guard_trips = watcher.guard_trips;
  const double end_s = std::max(report.sim_time_s, report.final_time_s.value_or(0.0));
  o.sim_time_s = end_s;
  o.max_depth_m = watcher.max_depth_m;
  if (report.final_depth_m) o.max_depth_m = std::max(o.max_depth_m.value_or(0.0), *report.final_depth_m);
  if (c.fault) {
    o.fault_at_s = c.fault->at_s;
    o.fault_reached = end_s >= c.fault->at_s;
    o.bound_to_at_s = watcher.bound_to_at_s;
    o.bound_to_before_s = watcher.bound_to_before_s;
    if (watcher.surfaced_at_s) {
      o.time_to_surface_s = tidy_s(std::max(0.0, *watcher.surfaced_at_s - c.fault->at_s));
      o.surface_seen = "telemetry";
    } else if (watcher.logged_surface_s) {
      o.time_to_surface_s = tidy_s(std::max(0.0, *watcher.logged_surface_s - c.fault->at_s));
      o.surface_seen = "vehicle log";
    } else if (o.fault_reached && report.final_depth_m && *report.final_depth_m <= surface_depth_m &&
               report.final_time_s) {
      o.time_to_surface_s = tidy_s(std::max(0.0, *report.final_time_s - c.fault->at_s));
      o.surface_seen = "final state";
    }
  }
  std::optional<double> first_refused_s;
  for (const tactical::CallRecord& call : report.trace) {
    if (!refused_exec(call)) continue;
    if (o.refused_execs++ == 0) {
      first_refused_s = call.sim_time_s;
      o.first_refused = fmt::format("{} at {:.1f} s{}", call.message, call.sim_time_s,
                                    call.error ? ": " + call.error->message : ": answered 0");
    }
  }
  if (!report.vehicle_reason.empty() && !o.first_refused.empty()) o.first_refused += " (" + report.vehicle_reason + ")";
  // The trace holds the vehicle's answers; an EXEC the script failed where
  // the vehicle did it (`answers`) is only in the log's scripted_answer.
  for (const ScriptedExecFailure& f : scripted_failures) {
    ++o.refused_execs;
    if (!first_refused_s || f.sim_time_s < *first_refused_s) {
      first_refused_s = f.sim_time_s;
      o.first_refused =
          fmt::format("exec {} at {:.1f} s: the script answered 0 ({})", f.primitive, f.sim_time_s, f.where);
    }
  }
  if (report.answers_total > 0) {
    o.answers_used = report.answers_used;
    o.answers_total = report.answers_total;
    o.answers_diverged = report.answers_diverged;
    o.answers_first_unused = report.answers_first_unused;
  }
  return o;
}

nlohmann::ordered_json result_line(const Spec& spec, const Case& c, const Observation& seen,
                                   const BoundProof* proof = nullptr) {
  nlohmann::ordered_json j;
  j["index"] = c.index;
  j["inputs"] = case_inputs(spec, c);
  j["outcome"] = seen.outcome;
  j["reason"] = seen.reason;
  if (!seen.stopped_by.empty()) j["stopped_by"] = seen.stopped_by;
  const std::vector<Check> checks = evaluate(spec.expectations.at(spec.families[c.family].expect), seen, proof);
  bool pass = true;
  nlohmann::ordered_json arr = nlohmann::ordered_json::array();
  for (const Check& check : checks) {
    pass = pass && check.pass;
    arr.push_back(to_json(check));
  }
  j["pass"] = pass;
  j["expect"] = spec.families[c.family].expect;
  j["checks"] = std::move(arr);
  nlohmann::ordered_json figures;
  figures["sim_time_s"] = seen.sim_time_s;
  figures["max_depth_m"] = seen.max_depth_m ? nlohmann::ordered_json(*seen.max_depth_m) : nullptr;
  figures["time_to_surface_s"] = seen.time_to_surface_s ? nlohmann::ordered_json(*seen.time_to_surface_s) : nullptr;
  if (!seen.surface_seen.empty()) figures["surface_seen"] = seen.surface_seen;
  figures["refused_execs"] = seen.refused_execs;
  j["figures"] = std::move(figures);
  return j;
}

}  // namespace

std::string repro_command(const Spec& spec, const Case& c) {
  return fmt::format("strata campaign {} --case {}", shell_quote(spec.path), c.index);
}

std::vector<std::string> repro_run_args(const Spec& spec, const Case& c, const std::string& scenario_file,
                                        const std::string& case_params_file) {
  std::vector<std::string> args{"run", spec.missions[c.mission].resolved, "--scenario", scenario_file};
  if (!case_params_file.empty()) {
    args.insert(args.end(), {"--params", case_params_file});
  } else if (!spec.params.empty()) {
    args.insert(args.end(), {"--params", spec.params_resolved});
  }
  args.insert(args.end(), {"--max-sim-time", fmt::format("{}", spec.max_sim_time_s), "--telemetry-hz",
                           fmt::format("{}", spec.telemetry_hz)});
  const Family& family = spec.families[c.family];
  if (!family.answers.empty()) args.insert(args.end(), {"--answers", family.answers_resolved});
  return args;
}

namespace {

// One run of a case: its result line (without the files kept and the
// timings) and, when asked for, its mission log.
struct CaseRun {
  nlohmann::ordered_json line;
  bool logged = false;
  std::string log;
  double run_wall_s = 0.0;
};

CaseRun run_case_once(const Spec& spec, const Case& c, const std::string& scenario, bool with_log) {
  const Mission& mission = spec.missions[c.mission];
  run::RunOptions o;
  o.mission = mission.resolved;
  o.scenario = kScenarioName;
  o.read_file = [&scenario](const std::string& path) -> core::Result<std::string> {
    if (path == kScenarioName) return scenario;
    // A mission file is what its name says, as for `strata run`
    // (coral::DiskFileProvider): a link x.coral to a file that is not is
    // not read.
    return core::read_regular_file_as_named(path, kMaxMissionFileBytes, ".coral");
  };
  o.max_sim_time_s = spec.max_sim_time_s;
  o.telemetry_hz = spec.telemetry_hz;
  o.trace = true;
  o.keep_mission = true;  // a worker runs one mission case after case
  // A case's log is kept in memory until the case ends: a runaway case must
  // not take a worker's memory (an hour's survey logs a few MB).
  o.max_log_bytes = kMaxCaseLogBytes;
  const Family& family = spec.families[c.family];
  o.answers = family.answers_resolved;
  o.params = spec.params_resolved;
  o.param_overrides = c.params;
  std::ostringstream log;
  if (with_log) {
    o.log_stream = &log;
    o.log = fmt::format("logs/case-{}.jsonl", c.index);
  }
  const vehicle::VehicleParams params = case_params(spec, c);
  const double surface_depth_m = params.surface_depth_m;  // perturbed, when it is
  const ExpectationSet& set = spec.expectations.at(family.expect);
  std::optional<BoundProof> proof;
  if (set.bound) proof = proven_bound(spec, c.mission, set, params);
  CaseWatcher watcher(c.fault ? std::optional<double>(c.fault->at_s) : std::nullopt, surface_depth_m,
                      set.bound ? &*set.bound : nullptr);
  run::RunSession session(std::move(o));
  session.add_observer(watcher);
  const run::RunReport report = session.run();
  watcher.finish();
  const Observation seen =
      observe(report, watcher, c, surface_depth_m,
              family.answers.empty() ? std::vector<ScriptedExecFailure>{} : scripted_exec_failures(log.str()));

  CaseRun out;
  out.line = result_line(spec, c, seen, proof ? &*proof : nullptr);
  if (report.result) out.line["exit"] = report.result->exit;
  out.line["phases"] = report.phases;
  out.line["coverage"] = watcher.coverage();
  out.logged = with_log && report.result;
  if (out.logged) out.log = log.str();
  out.run_wall_s = report.wall_time_s;
  return out;
}

}  // namespace

nlohmann::ordered_json run_case(const Spec& spec, const Case& c, const CaseRunConfig& config) {
  const auto wall_start = std::chrono::steady_clock::now();
  const std::string scenario = scenario_toml(spec, c);
  const bool folder = !config.out_dir.empty();
  // A mission log costs about a third of a run, and most cases pass. So it
  // is written as the case runs only when it is always kept, or when the
  // scripted answers' failures are read from it; a failing case whose log
  // is to be kept runs again with it (a lockstep run goes the same way
  // every time). When that run gives another line (a wall-clock limit, or
  // the log's own size limit, which the first run did not have), its log is
  // kept all the same, with log_note saying how that run ended.
  const bool log_now = (folder && config.keep_logs == KeepLogs::All) || !spec.families[c.family].answers.empty();
  CaseRun first = run_case_once(spec, c, scenario, log_now);
  nlohmann::ordered_json& j = first.line;
  double run_wall_s = first.run_wall_s;
  const bool pass = j["pass"].get<bool>();
  if (folder && !pass && config.keep_logs == KeepLogs::Failed && !first.logged) {
    if (config.on_run_again) config.on_run_again();
    CaseRun again = run_case_once(spec, c, scenario, true);
    run_wall_s += again.run_wall_s;
    if (again.line != j) {
      const std::string reason = again.line.value("reason", std::string());
      j["log_note"] = fmt::format("the log is of the case run again to write it, which went another way ({}{}{})",
                                  again.line.value("outcome", std::string("?")), reason.empty() ? "" : ": ", reason);
    }
    first.logged = again.logged;
    first.log = std::move(again.log);
  }
  const std::string log_name = fmt::format("case-{}.jsonl", c.index);

  if (!config.out_dir.empty()) {
    const bool keep = config.keep_logs == KeepLogs::All || (config.keep_logs == KeepLogs::Failed && !pass);
    if (keep && first.logged && write_new_file(config.out_dir + "/logs/" + log_name, first.log)) {
      j["log"] = "logs/" + log_name;
    }
    if (!pass) {
      const std::string file = fmt::format("scenarios/case-{}.toml", c.index);
      // A perturbed vehicle travels as a whole parameter file (--params).
      const std::string params_file = fmt::format("scenarios/case-{}.params.toml", c.index);
      const vehicle::VehicleParams params = case_params(spec, c);
      const bool params_kept =
          !c.params.empty() && write_new_file(config.out_dir + "/" + params_file, vehicle::params_toml(params));
      if (params_kept) j["params_file"] = params_file;
      if (write_new_file(config.out_dir + "/" + file, scenario) && (c.params.empty() || params_kept)) {
        j["scenario"] = file;
        std::string line = "strata";
        for (const std::string& a : repro_run_args(spec, c, config.out_dir + "/" + file,
                                                   params_kept ? config.out_dir + "/" + params_file : "")) {
          line += " " + shell_quote(a);
        }
        j["repro_run"] = std::move(line);
      }
    }
  }
  if (!pass) j["repro"] = repro_command(spec, c);
  j["timings"] = {{"wall_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count()},
                  {"run_wall_s", run_wall_s},
                  {"pid", static_cast<long>(::getpid())}};
  return std::move(first.line);
}

nlohmann::ordered_json crashed_case(const Spec& spec, const Case& c, const std::string& why) {
  Observation seen;
  seen.outcome = "crashed";
  seen.reason = why;
  nlohmann::ordered_json j = result_line(spec, c, seen);
  j["repro"] = repro_command(spec, c);
  j["timings"] = {{"wall_s", nullptr}};
  return j;
}

}  // namespace strata::campaign
