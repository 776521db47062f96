// `strata compare A B`: runs two missions (CORAL or PROLOG, in any mix)
// against identical simulated vehicles and prints their primitive-call
// traces side by side, marking the first difference.
#include <iostream>
#include <memory>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/mission_run.h"
#include "cli/rule_load_flags.h"
#include "cli/run_flags.h"
#include "cli/trace_compare.h"
#include "cli/verbosity.h"
#include "core/mission_language.h"
#include "tactical/execution_level.h"

namespace strata::cli {
namespace {

struct CompareOptions {
  std::string a, b;
  std::string vehicle_a, vehicle_b;  // --vehicle-a/-b: "" the embedded vehicle
  double speed = 1.0;                // the speed of a vehicle of its own (an IMC one's FollowReference timeout)
  std::string scenario;
  std::optional<std::uint64_t> seed;
  std::string params;
  std::string catalogue;
  std::uint64_t inference_limit = RunOptions{}.inference_limit;
  run::RuleLoadLimits rule_load;
  RunOptions shared;  // --data, --max-sim-time, --telemetry-hz: for both runs
  std::optional<std::size_t> context;
  std::string format = "text";
  VerbosityFlags verbosity;
};

std::string language(const std::string& path) {
  return core::mission_language(path) == core::MissionLanguage::Prolog ? "PROLOG" : "CORAL";
}

tactical::ExecutionLevel level_of(const std::string& vehicle) { return tactical::execution_level_of(vehicle); }

bool embedded(const std::string& vehicle) { return vehicle.empty() || vehicle == "embedded"; }

// Whether a side runs on a vehicle of its own (another execution level, or a
// vehicle on its own clock): then the runs' commands are compared, not every
// call with its time (trace_compare.h, command_rows).
bool across_levels(const CompareOptions& o) {
  return level_of(o.vehicle_a) != level_of(o.vehicle_b) || !embedded(o.vehicle_a) || !embedded(o.vehicle_b);
}

std::string outcome_text(const RunReport& r) {
  if (!r.result) return "did not start";
  std::string text(strategic::to_string(r.result->outcome));
  if (!r.result->reason.empty()) text += " (" + r.result->reason + ")";
  return text;
}

nlohmann::json row_json(const std::vector<TraceRow>& rows, std::size_t i) {
  if (i >= rows.size()) return nullptr;
  return {{"call", rows[i].call}, {"answer", rows[i].answer}, {"sim_time_s", rows[i].sim_time_s}};
}

// `--format json`: both runs, and where their traces part (docs/architecture.md).
nlohmann::json comparison_json(const CompareOptions& o, const RunReport (&reports)[2], const std::vector<TraceRow>& a,
                               const std::vector<TraceRow>& b, std::optional<std::size_t> diff) {
  auto side = [](const std::string& path, const std::string& vehicle, const RunReport& r) {
    return nlohmann::json{{"mission", path},
                          {"language", language(path)},
                          {"execution_level", level_of(vehicle) == tactical::ExecutionLevel::Imc ? "imc" : "phoenix"},
                          {"outcome", std::string(strategic::to_string(r.result->outcome))},
                          {"reason", r.result->reason},
                          {"calls", r.trace.size()},
                          {"sim_time_s", r.sim_time_s}};
  };
  nlohmann::json j{{"a", side(o.a, o.vehicle_a, reports[0])},
                   {"b", side(o.b, o.vehicle_b, reports[1])},
                   {"compared", across_levels(o) ? "commands" : "calls"},
                   {"scenario", o.scenario.empty() ? "nominal" : o.scenario},
                   {"seed", o.seed ? nlohmann::json(*o.seed) : nlohmann::json(nullptr)},
                   {"same_outcome", reports[0].result->outcome == reports[1].result->outcome},
                   {"first_difference", nullptr}};
  j["identical"] = !diff && j["same_outcome"].get<bool>();
  if (diff) j["first_difference"] = {{"call", *diff + 1}, {"a", row_json(a, *diff)}, {"b", row_json(b, *diff)}};
  return j;
}

int run_compare(const CompareOptions& o) {
  RunReport reports[2];
  const std::string* paths[2] = {&o.a, &o.b};
  for (int i = 0; i < 2; ++i) {
    RunOptions run;
    run.data = o.shared.data;
    run.max_sim_time_s = o.shared.max_sim_time_s;
    run.telemetry_hz = o.shared.telemetry_hz;
    run.mission = *paths[i];
    run.vehicle = i == 0 ? o.vehicle_a : o.vehicle_b;
    run.speed = o.speed;
    // A vehicle of its own was started with its scenario and parameters.
    const bool own = !embedded(run.vehicle);
    if (!own) run.vehicle.clear();
    if (own && (!o.scenario.empty() || !o.params.empty())) {
      std::cerr << fmt::format(
          "strata compare: note: {} runs on {}, which has its own scenario and parameters; "
          "--scenario and --params are for the embedded vehicle\n",
          i == 0 ? "A" : "B", run.vehicle);
    }
    run.scenario = own ? "" : o.scenario;
    run.seed = o.seed;
    run.params = own ? "" : o.params;
    run.catalogue = o.catalogue;
    run.inference_limit = o.inference_limit;
    run.rule_load = o.rule_load;
    run.trace = true;
    std::ostringstream out, err;
    reports[i] = run_mission(run, out, err);
    if (!reports[i].result) {
      // It never ran: a usage error, a bad mission, a file not there.
      std::cerr << err.str();
      std::cerr << fmt::format("strata compare: {} did not run\n", *paths[i]);
      return reports[i].exit_code == kExitOk ? kExitInternal : reports[i].exit_code;
    }
  }
  const bool commands = across_levels(o);
  const auto rows_a = commands ? command_rows(trace_rows(reports[0].trace)) : trace_rows(reports[0].trace);
  const auto rows_b = commands ? command_rows(trace_rows(reports[1].trace)) : trace_rows(reports[1].trace);
  const auto diff = first_difference(rows_a, rows_b);
  const bool same_outcome = reports[0].result->outcome == reports[1].result->outcome;
  const int exit = !diff && same_outcome ? kExitOk : kExitAbort;
  if (o.format == "json") {
    std::cout << comparison_json(o, reports, rows_a, rows_b, diff).dump(2) << "\n";
    return exit;
  }
  const bool quiet = o.verbosity.level() == Verbosity::Quiet;
  for (int i = 0; i < 2 && !quiet; ++i) {
    std::cout << fmt::format("{}: {} ({}): {}, {} calls, {:.1f} s simulated\n", i == 0 ? "A" : "B", *paths[i],
                             language(*paths[i]), outcome_text(reports[i]), reports[i].trace.size(),
                             reports[i].sim_time_s);
  }
  if (!quiet) {
    std::cout << fmt::format("scenario {}{}\n", o.scenario.empty() ? "nominal" : o.scenario,
                             o.seed ? fmt::format(", seed {}", *o.seed) : "");
    if (commands) {
      std::cout << fmt::format(
          "across vehicles (A: {}, B: {}): their commands compared in order (exec, ood, report; a run of "
          "the same command, as a poll loop's sleep, counted once); asks and times depend on the vehicle\n",
          tactical::execution_level_name(level_of(o.vehicle_a)), tactical::execution_level_name(level_of(o.vehicle_b)));
    }
    std::cout << "\n";
    SideBySideOptions table{"A: " + o.a, "B: " + o.b, o.context};
    std::cout << side_by_side(rows_a, rows_b, table) << "\n";
  }
  if (!diff && same_outcome) {
    if (commands) {
      std::cout << fmt::format("identical: {} commands in the same order with the same answers; both {}\n",
                               rows_a.size(), strategic::to_string(reports[0].result->outcome));
      return kExitOk;
    }
    std::cout << fmt::format(
        "identical: {} primitive calls, the same answers at the same simulated times; "
        "both {}\n",
        rows_a.size(), strategic::to_string(reports[0].result->outcome));
    return kExitOk;
  }
  if (diff) {
    std::cout << fmt::format("different: the traces part at call {} (A made {} calls, B {})\n", *diff + 1,
                             rows_a.size(), rows_b.size());
  }
  if (!same_outcome) {
    std::cout << fmt::format("different outcomes: A {}, B {}\n", strategic::to_string(reports[0].result->outcome),
                             strategic::to_string(reports[1].result->outcome));
  }
  return exit;
}

}  // namespace

Runner add_compare_command(CLI::App& app) {
  auto o = std::make_shared<CompareOptions>();
  auto* cmd =
      app.add_subcommand("compare",
                         "Run two missions (.coral or .pl, in any mix) against identical simulated vehicles and print "
                         "their primitive-call traces side by side; exit 0 when identical, 1 when not");
  cmd->add_option("a", o->a, "The first mission")->required();
  cmd->add_option("b", o->b, "The second mission")->required();
  cmd->add_option("--vehicle-a", o->vehicle_a,
                  "The vehicle A runs against, as `strata run --vehicle` takes it (default: an embedded one)");
  cmd->add_option("--vehicle-b", o->vehicle_b,
                  "The vehicle B runs against, e.g. imc://127.0.0.1:6002 (`strata vehicle --imc`); across "
                  "execution levels the commands are compared, not the asks and times");
  cmd->add_option("--speed", o->speed,
                  "With --vehicle-a/-b: simulated seconds per wall second of that vehicle (`strata vehicle --speed`)")
      ->check(CLI::Range(0.01, 1000.0))
      ->capture_default_str();
  cmd->add_option("--scenario", o->scenario,
                  "Vehicle scenario for the runs on an embedded vehicle (a vehicle of its own was started with its "
                  "own): NAME in each mission's scenarios/ folder, or a path "
                  "(default: nominal)");
  cmd->add_option("--seed", o->seed, "CORAL: choose among enabled transitions at random, from this seed");
  cmd->add_option("--params", o->params, "Vehicle parameter file (default: built in)");
  cmd->add_option("--catalogue", o->catalogue, "Primitive catalogue (default: built in)");
  cmd->add_option("--inference-limit", o->inference_limit, "PROLOG: inferences allowed between two primitive calls")
      ->check(CLI::Range(std::uint64_t{1000}, std::uint64_t{1'000'000'000'000}))
      ->capture_default_str();
  add_rule_load_flags(cmd, o->rule_load);
  add_shared_run_flags(cmd, o->shared);
  cmd->add_option("--context", o->context,
                  "Show only this many calls around the first difference (default: every call)");
  cmd->add_option("--format", o->format,
                  "text, or json: both runs' outcomes and the first difference as one JSON document")
      ->check(CLI::IsMember({"text", "json"}))
      ->capture_default_str();
  add_verbosity_flags(cmd, o->verbosity, "");
  return [o] { return run_compare(*o); };
}

}  // namespace strata::cli
