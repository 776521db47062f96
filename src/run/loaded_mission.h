#pragma once
// A run's inputs, loaded and checked before anything moves: the catalogue,
// the mission (CORAL compiled and verified, or PROLOG rules loaded and
// checked), the vehicle's parameters and scenario, the mission data.
#include <memory>
#include <optional>
#include <vector>
#include <string>

#include <nlohmann/json.hpp>

#include "coral/program.h"
#include "coral/verifier.h"
#include "core/diagnostic.h"
#include "core/source.h"
#include "strategic/prolog_mission.h"
#include "run/answers.h"
#include "run/error.h"
#include "run/options.h"
#include "tactical/catalogue.h"
#include "tactical/mission_data.h"
#include "tactical/mission_log.h"
#include "vehicle/params.h"
#include "vehicle/scenario.h"

namespace strata::run {

struct LoadedMission {
  LoadedMission() = default;
  LoadedMission(const LoadedMission&) = delete;  // the cursor points into data
  LoadedMission& operator=(const LoadedMission&) = delete;

  tactical::Catalogue catalogue;
  core::SourceManager sources;
  // What the load found in the mission text (CORAL or PROLOG), warnings
  // too, placed in `sources`, for the caller to print.
  std::vector<core::Diagnostic> diagnostics;
  std::optional<coral::Program> program;            // a .coral mission
  std::unique_ptr<strategic::PrologMission> rules;  // a .pl mission
  std::string name;                                 // the mission net's name, or the rules' file stem
  std::string data_path;                            // the data file used; "" none
  std::optional<tactical::MissionData> data;
  std::optional<tactical::DataCursor> cursor;
  vehicle::VehicleParams params;
  vehicle::Scenario scenario;
  // Where the scenario came from, for the run's header: the file read, or
  // why the built-in one ("built in: no scenarios/nominal.toml beside
  // the mission").
  std::string scenario_origin;
  // CORAL: the verification. A run goes on with a report that is not ok()
  // only with --unverified or --answers; one that is ok() but not
  // all_hold() is information, not a veto.
  std::optional<coral::VerifyReport> verification;
  std::optional<AnswerScript> answers;  // --answers: checked against the mission
  // CORAL, RunOptions::keep_mission: the program and its verification were
  // taken back from an earlier run in this process, not compiled again.
  bool taken_back = false;
};

// Loads everything the options name into `loaded`, stopping at the first
// problem. Nothing is printed: what the mission text holds (warnings too)
// is in loaded.diagnostics and loaded.rule_messages either way.
core::Result<void, Error> load_mission(const RunOptions& options, LoadedMission& loaded);

// The strategic::LoadLimits of the options' limits.
strategic::LoadLimits load_limits(const RuleLoadLimits& limits);

// Where the options' scenario is read from (LoadedMission::scenario_origin).
std::string scenario_origin(const RunOptions& options);
// The scenario's name as the log and the console give it ("nominal" for none).
std::string scenario_name(const RunOptions& options);
// The mission log's header: which inputs made this run.
tactical::RunInfo run_info(const RunOptions& options, const LoadedMission& loaded);
// What the log keeps of the verification: whether it passed, and each
// property that did not hold, with its message.
nlohmann::json verification_record(const coral::VerifyReport& v, bool unverified);

}  // namespace strata::run
