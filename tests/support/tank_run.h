#pragma once
// Shared by the `strata run` tests: the tank mission run in-process through
// cli::run_mission with a mission log in a temp folder, the log parsed into
// its calls, phases and lines, and each scenario run once per process.
//
// Bounds come from the inputs, not from the current output: the setpoints and
// their time limits (missions/tank/setpoints.toml), the fault times
// (missions/tank/scenarios/*.toml) and the vehicle's thresholds
// (vehicle::default_params(), the same as config/phoenix.toml).
#include <stdlib.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/mission_run.h"
#include "tactical/mission_data.h"
#include "tactical/mission_log.h"
#include "vehicle/params.h"
#include "vehicle/scenario.h"

namespace strata::cli::run_testing {

namespace fs = std::filesystem;
using json = nlohmann::json;
using strategic::Outcome;
using namespace std::chrono_literals;

inline const std::string kTankDir = std::string(STRATA_SOURCE_DIR) + "/missions/tank";
inline const std::string kMission = kTankDir + "/tank.coral";
// A reply and the next request carry the same sim_time; logged times are
// rounded to the microsecond.
constexpr double kEps = 1e-6;
// One monitoring cycle of phases 2 and 3: sleep(1) and three questions of
// one 0.1 s cycle each (the scenario files' "within 1.3 s").
constexpr double kMonitoringCycleS = 1.3;

// A fresh folder under the test temp dir, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::path(::testing::TempDir()) / "strata_run_XXXXXX").string();
    if (char* made = mkdtemp(pattern.data())) path_ = made;
    EXPECT_FALSE(path_.empty()) << "mkdtemp failed for " << pattern;
  }
  ~TempDir() {
    std::error_code ec;
    if (!path_.empty()) fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

// One primitive call to the vehicle, from its `request` line and the `reply`
// line of the same id.
struct Call {
  std::uint64_t id = 0;
  std::string primitive;
  std::string phase;  // the depth-1 phase running when it was requested; "" for the mission net
  double requested_s = 0;
  std::size_t request_line = 0;
  std::optional<json> result;  // 1 / 0, or {"error": ...}
  double replied_s = 0;
  std::size_t reply_line = 0;

  bool answered(int value) const { return result && result->is_number_integer() && *result == value; }
  bool failed() const { return result && result->is_object() && result->contains("error"); }
  bool is(std::string_view name, int value) const { return primitive == name && answered(value); }
};

struct PhaseEndLine {
  std::string net;
  std::string result;  // completed | aborted | cancelled
  double sim_time_s = 0;
  std::size_t line = 0;
};

struct ParsedLog {
  std::string text;
  std::vector<json> lines;
  std::vector<Call> calls;               // in request order
  std::vector<PhaseEndLine> phase_ends;  // depth 1 only
  std::vector<std::string> started;      // depth-1 phases, in start order
  std::vector<std::size_t> report_lines;
  std::vector<double> telemetry_depths_m;
  std::optional<std::size_t> mission_end, emergency, vehicle_final;

  const json& at(std::optional<std::size_t> i) const { return lines.at(i.value()); }
  std::vector<std::string> phases() const {
    std::vector<std::string> out;
    for (const auto& p : phase_ends) out.push_back(p.net + " " + p.result);
    return out;
  }
  std::vector<const Call*> in_phase(std::string_view phase) const {
    std::vector<const Call*> out;
    for (const auto& c : calls) {
      if (c.phase == phase) out.push_back(&c);
    }
    return out;
  }
  const Call* first(const std::function<bool(const Call&)>& pred) const {
    for (const auto& c : calls) {
      if (pred(c)) return &c;
    }
    return nullptr;
  }
  std::size_t count(const std::function<bool(const Call&)>& pred) const {
    return static_cast<std::size_t>(std::count_if(calls.begin(), calls.end(), pred));
  }
};

inline std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline ParsedLog parse_log(const std::string& text) {
  ParsedLog log;
  log.text = text;
  std::istringstream in(text);
  std::string line;
  std::map<std::uint64_t, std::size_t> call_of_id;
  std::map<std::uint64_t, std::size_t> depth_of_instance;
  std::map<std::uint64_t, std::string> phase_of_instance;
  std::string current_phase;
  while (std::getline(in, line)) {
    json j = json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object() || !j.contains("event")) {
      ADD_FAILURE() << "log line " << log.lines.size() + 1 << " is not a JSON event: " << line;
      continue;
    }
    const std::size_t n = log.lines.size();
    const std::string event = j["event"];
    if (event == "phase_start") {
      depth_of_instance[j["instance"]] = j["depth"];
      if (j["depth"] == 1) {
        current_phase = j["net"];
        log.started.push_back(current_phase);
        phase_of_instance[j["instance"]] = current_phase;
      }
    } else if (event == "phase_end") {
      if (depth_of_instance[j["instance"]] == 1) {
        log.phase_ends.push_back({j["net"], j["result"], j["sim_time"], n});
        current_phase.clear();
      }
    } else if (event == "request") {
      call_of_id[j["id"]] = log.calls.size();
      log.calls.push_back({j["id"], j["primitive"], current_phase, j["sim_time"], n, std::nullopt, 0, 0});
    } else if (event == "reply") {
      auto it = call_of_id.find(j["id"]);
      if (it == call_of_id.end()) {
        ADD_FAILURE() << "reply without a request: " << line;
      } else {
        Call& c = log.calls[it->second];
        EXPECT_FALSE(c.result.has_value()) << "second reply for request " << c.id;
        c.result = j["result"];
        c.replied_s = j["sim_time"];
        c.reply_line = n;
      }
    } else if (event == "report") {
      log.report_lines.push_back(n);
    } else if (event == "telemetry") {
      if (j.contains("depth_m")) log.telemetry_depths_m.push_back(j["depth_m"]);
    } else if (event == "mission_end") {
      EXPECT_FALSE(log.mission_end.has_value()) << "two mission_end lines";
      log.mission_end = n;
    } else if (event == "emergency") {
      log.emergency = n;
    } else if (event == "vehicle_final") {
      log.vehicle_final = n;
    }
    log.lines.push_back(std::move(j));
  }
  return log;
}

struct MissionRun {
  RunReport report;
  std::string out, err;
  ParsedLog log;
  std::string log_path;
};

// Runs a mission with a mission log in a temp folder, and parses the log.
inline MissionRun run_logged(RunOptions o) {
  TempDir dir;
  o.log = dir.file("mission.jsonl");
  std::ostringstream out, err;
  MissionRun run;
  run.report = run_mission(o, out, err);
  run.out = out.str();
  run.err = err.str();
  run.log_path = o.log;
  run.log = parse_log(read_file(o.log));
  return run;
}

inline MissionRun run_tank(const std::string& scenario, std::optional<std::uint64_t> seed = std::nullopt,
                           const std::string& vehicle = "") {
  RunOptions o;
  o.mission = kMission;
  o.scenario = scenario;
  o.seed = seed;
  o.vehicle = vehicle;
  return run_logged(std::move(o));
}

// Each scenario once per process, shared by the tests that only read it
// (ctest runs each test in its own process; a plain run of the binary shares).
inline const MissionRun& scenario_run(const std::string& name) {
  static std::map<std::string, MissionRun> runs;
  auto it = runs.find(name);
  if (it == runs.end()) it = runs.emplace(name, run_tank(name)).first;
  return it->second;
}

// The tank mission's data: one setpoint per phase 2, 3, 4.
inline std::vector<tactical::Setpoint> setpoints() {
  auto d = tactical::MissionData::load(kTankDir + "/setpoints.toml");
  EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.error().message);
  std::vector<tactical::Setpoint> out = d.ok() ? d.value().setpoints() : std::vector<tactical::Setpoint>{};
  EXPECT_EQ(3u, out.size());
  out.resize(3);
  return out;
}

inline vehicle::Fault fault_of(const std::string& scenario, vehicle::FaultKind kind) {
  auto s = vehicle::load_scenario(kTankDir + "/scenarios/" + scenario + ".toml");
  EXPECT_TRUE(s.ok()) << scenario;
  if (s.ok()) {
    for (const auto& f : s.value().faults) {
      if (f.kind == kind) return f;
    }
  }
  ADD_FAILURE() << scenario << " has no " << vehicle::to_string(kind) << " fault";
  return {};
}

inline const vehicle::VehicleParams kParams = vehicle::default_params();

}  // namespace strata::cli::run_testing
