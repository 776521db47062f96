// `strata verify MISSION`: the mission's nets verified before they run
// (coral/verifier.h). `strata verify --pnml FILE`: the reachability graph of
// a P/T net in PNML, explored in full, and the Model Checking Contest's
// global properties.
#include <iostream>
#include <memory>
#include <new>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/validators.h"
#include "cli/verbosity.h"
#include "cli/commands.h"
#include "cli/run_problems.h"
#include "run/bound_options.h"
#include "run/coral_load.h"
#include "cli/exit_codes.h"
#include "cli/pnml_verify.h"
#include "cli/verify_question.h"
#include "cli/witness_out.h"
#include "cli/verify_bound.h"
#include "coral/timing.h"
#include "coral/verify_report.h"
#include "core/mission_language.h"

namespace strata::cli {
namespace {

struct VerifyOptions {
  std::string mission;
  std::string catalogue;
  std::uint64_t max_states = 1'000'000;  // MISSION; --pnml: none unless given
  bool max_states_given = false;
  std::string pnml;
  std::string format = "text";
  std::size_t max_memory_mb = coral::kDefaultVerifyMemoryBytes >> 20;  // MISSION; --pnml: none unless given
  bool max_memory_given = false;
  double time_limit_s = 0;  // 0: none
  bool no_liveness = false;
  VerbosityFlags verbosity;
  std::string witness_out;  // MISSION: a counterexample as an answers file
  std::string witness_net;  // ... from this net only ("" any)
};

// --format json: one document on stdout whatever happens; a mission that
// does not get as far as verification has no nets and says why.
void print_unverified_json(const std::string& error, const nlohmann::json& diagnostics) {
  nlohmann::ordered_json j{{"ok", false}, {"all_hold", false}};
  if (!error.empty()) j["error"] = error;
  j["diagnostics"] = diagnostics.is_array() ? diagnostics : nlohmann::json::array();
  j["nets"] = nlohmann::ordered_json::array();
  std::cout << j.dump(2) << "\n";
}

int run_verify_mission(const VerifyOptions& o) {
  const bool json = o.format == "json";
  if (core::mission_language(o.mission) != core::MissionLanguage::Coral) {
    const std::string error = fmt::format(
        "'{}' is not a CORAL mission (.coral); PROLOG rules are not nets (`strata run` checks them at load, "
        "docs/prolog.md), and a PNML net needs --pnml",
        o.mission);
    std::cerr << "strata verify: " << error << "\n";
    if (json) print_unverified_json(error, nullptr);
    return kExitUsage;
  }
  auto catalogue = load_catalogue_option(o.catalogue);
  if (!catalogue) {
    std::cerr << "strata verify: " << catalogue.error().message << "\n";
    if (json) print_unverified_json(catalogue.error().message, nullptr);
    return exit_code_for_input(catalogue.error());
  }
  run::CoralLoad load = run::load_coral_file(o.mission, catalogue.value());
  if (int code = print_coral_load(std::cerr, load, "strata verify"); code != kExitOk) {
    if (json) print_unverified_json("the mission does not compile", load.diagnostics_json());
    return code;
  }
  coral::VerifyOptions vo;
  vo.max_states = o.max_states;
  vo.max_memory_bytes = o.max_memory_mb << 20;
  vo.time_limit_s = o.time_limit_s;
  vo.sources = &load.sources;
  vo.timing = run::bound_options(catalogue.value());
  if (load.program->nets.empty()) {
    // Nothing was verified, so nothing holds: a file of comments is no mission.
    const std::string why = fmt::format("{}: no net to verify (the file declares none)", o.mission);
    if (json) print_unverified_json(why, load.diagnostics_json());
    std::cerr << "strata verify: " << why << "\n";
    return kExitInvalid;
  }
  const coral::VerifyReport report = coral::verify_program(*load.program, vo);
  if (json) {
    nlohmann::ordered_json j = coral::verify_json(report);
    j["diagnostics"] = load.diagnostics_json();  // warnings
    std::cout << j.dump(2) << "\n";
  } else {
    // Quiet: only the nets with a problem; the default adds a line for
    // each net that is fine; verbose shows every property of every net.
    const Verbosity level = o.verbosity.level();
    std::cout << coral::verify_text(report, level == Verbosity::Quiet     ? coral::VerifyDetail::Problems
                                            : level == Verbosity::Verbose ? coral::VerifyDetail::Full
                                                                          : coral::VerifyDetail::Nets);
  }
  if (!o.witness_out.empty()) {
    const int written = write_report_witness(report, o.mission, o.witness_net, o.witness_out);
    if (written == kExitUsage || written == kExitIo) return written;
  }
  if (report.ok()) return kExitOk;
  std::size_t failing = 0;
  for (const auto& n : report.nets) failing += n.ok() ? 0 : 1;
  std::cerr << fmt::format(
      "strata verify: {}: {} of {} nets with a property that fails or is not decided (the report "
      "says which, with the shortest way there); `strata run` refuses it until they hold\n",
      o.mission, failing, report.nets.size());
  return kExitInvalid;
}

}  // namespace

Runner add_verify_command(CLI::App& app) {
  auto o = std::make_shared<VerifyOptions>();
  auto* cmd = app.add_subcommand(
      "verify",
      "Verify a CORAL mission's nets before they run (bounds, 1-safety, dead transitions, deadlocks, traps, "
      "exits), with the shortest counterexamples; or explore a P/T net in PNML (--pnml FILE)");
  auto* mission = cmd->add_option("mission", o->mission, "A CORAL mission or library (.coral)");
  auto* pnml = cmd->add_option("--pnml", o->pnml, "A place/transition net in PNML (ISO/IEC 15909-2)");
  mission->excludes(pnml);
  pnml->excludes(mission);
  cmd->add_option("--catalogue", o->catalogue, "MISSION: primitive catalogue (default: built in)");
  cmd->add_option("--max-states", o->max_states,
                  "Stop exploring a net after this many markings (what needs the whole graph is then not decided; "
                  "default for --pnml: no limit)")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100'000'000}))
      ->capture_default_str();
  cmd->add_option("--format", o->format, "text or json")->check(CLI::IsMember({"text", "json"}))->capture_default_str();
  cmd->add_option("--max-memory", o->max_memory_mb,
                  "Stop each analysis step before the process would hold more than this many MB (what is not "
                  "settled is then not decided; 0: no limit; default for --pnml: no limit)")
      ->check(CLI::Range(std::size_t{0}, kMaxMemoryMb))
      ->capture_default_str();
  cmd->add_option("--time-limit", o->time_limit_s,
                  "Stop after this many seconds in all (what is not settled is then not decided; 0: none)")
      ->check(finite_range(0.0, 1e9))
      ->capture_default_str();
  cmd->add_flag("--no-liveness", o->no_liveness, "--pnml: skip the liveness pass (a second walk of the graph)");
  add_verbosity_flags(cmd, o->verbosity,
                      "Every property of every net, its place bounds and P-invariants (by default a net whose "
                      "properties all hold is one line; -q leaves those out)");
  auto q = std::make_shared<QuestionFlags>();
  add_question_options(*cmd, *q);
  auto bounds = std::make_shared<BoundFlags>();
  cmd->add_option("--bound", bounds->questions,
                  "MISSION: the reaction time, at worst and at best, from FROM to TO: 'fault ASK -> exec surface', "
                  "'trip GUARD -> surface within 30', 'start PHASE -> exit NAME' (docs/verification.md, \"Reaction "
                  "time\"); may be given more than once")
      ->allow_extra_args(false);
  cmd->add_option("--depth-max", bounds->depth_max_m,
                  "--bound ... -> surface: the deepest the vehicle can be, m, for the ascent estimate")
      ->check(finite_range(0.0, 11000.0))
      ->capture_default_str();
  cmd->add_option("--witness-out", q->witness_out,
                  "MISSION: write the counterexample of the first property that fails (in --net's net when given), "
                  "or with --question its witness, as the vehicle answers the path needs: `strata run MISSION "
                  "--answers FILE` follows it (docs/verification.md)");
  cmd->footer(
      "Exit, MISSION: 0 when the mission may run (every property that blocks `strata run` holds; one_safe and "
      "no_dead are warnings); 65 when one fails or is not decided, or the mission does not compile; 74 for a "
      "file it cannot open.\n"
      "Exit, --pnml: 0 when the graph was explored in full; 1 when a limit or Ctrl-C stopped it (a partial "
      "report); 65 for a net Strata cannot read; 74 for a file it cannot open. `strata-pnml FILE` does the same "
      "in a program that loads only the nets.");
  return [o, q, cmd, bounds] {
    o->max_states_given = cmd->count("--max-states") > 0;
    o->max_memory_given = cmd->count("--max-memory") > 0;
    if (o->mission.empty() && o->pnml.empty()) {
      std::cerr << "strata verify: give a mission (.coral) or --pnml FILE\n";
      return static_cast<int>(kExitUsage);
    }
    if (!q->witness_out.empty() && (!o->pnml.empty() || !q->replay.empty() || !q->replay_file.empty())) {
      std::cerr << "strata verify: --witness-out writes a mission's vehicle answers: it needs a MISSION, and not "
                   "--pnml or --replay\n";
      return static_cast<int>(kExitUsage);
    }
    o->witness_out = q->witness_out;
    o->witness_net = q->net;
    try {
      if (!bounds->questions.empty()) {
        if (!o->pnml.empty() || question_requested(*q) || !o->witness_out.empty()) {
          std::cerr << "strata verify: --bound asks about a MISSION, alone (not with --pnml, --question or "
                       "--witness-out)\n";
          return static_cast<int>(kExitUsage);
        }
        return run_mission_bounds(o->mission, o->catalogue, *bounds, o->format,
                                  o->max_states_given ? o->max_states : coral::BoundOptions{}.max_states,
                                  o->verbosity.level() == Verbosity::Verbose);
      }
      if (question_requested(*q)) {
        const bool is_mission = o->pnml.empty();
        const QuestionLimits limits{o->max_states_given ? o->max_states : 0,
                                    is_mission || o->max_memory_given ? o->max_memory_mb : 0, o->time_limit_s};
        return is_mission ? run_mission_question(o->mission, o->catalogue, *q, o->format, limits)
                          : run_pnml_question(o->pnml, *q, o->format, limits);
      }
      if (o->pnml.empty()) return run_verify_mission(*o);
      return run_verify_pnml(PnmlVerifyOptions{o->pnml, o->format, o->max_states_given ? o->max_states : 0,
                                               o->max_memory_given ? o->max_memory_mb : 0, o->time_limit_s,
                                               o->no_liveness});
    } catch (const std::bad_alloc&) {
      // Each analysis step catches its own; this is reading or compiling.
      std::cerr << "strata verify: out of memory before the analysis could start; nothing decided\n";
      if (o->format == "json" && o->pnml.empty() && !question_requested(*q))
        print_unverified_json("out of memory", nullptr);
      return static_cast<int>(o->pnml.empty() ? kExitInvalid : kExitAbort);
    }
  };
}

}  // namespace strata::cli
