// `strata verify MISSION`: the mission's nets verified before they run
// (coral/verifier.h). `strata verify --pnml FILE`: the reachability graph of
// a P/T net in PNML, explored in full, and the Model Checking Contest's
// global properties.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <iostream>
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "run/coral_load.h"
#include "cli/exit_codes.h"
#include "cli/verify_question.h"
#include "coral/verify_report.h"
#include "petri/explorer.h"
#include "petri/pnml.h"

namespace strata::cli {
namespace {

struct VerifyOptions {
  std::string mission;
  std::string catalogue;
  std::uint64_t max_states = 1'000'000;
  std::string pnml;
  std::string format = "text";
  std::size_t max_memory_mb = 0;
  bool no_liveness = false;
};

std::atomic<bool> g_interrupted{false};
extern "C" void on_interrupt(int) { g_interrupted = true; }

const char* yes_no(bool b) { return b ? "yes" : "no"; }

std::string human(double n) {
  if (n >= 1e9) return fmt::format("{:.2f} G", n / 1e9);
  if (n >= 1e6) return fmt::format("{:.2f} M", n / 1e6);
  if (n >= 1e3) return fmt::format("{:.1f} k", n / 1e3);
  return fmt::format("{:.0f}", n);
}

int run_verify_pnml(const VerifyOptions& o) {
  auto loaded = petri::read_pnml(o.pnml);
  if (!loaded) {
    std::cerr << "strata verify: " << loaded.error().message << "\n";
    return exit_code_for_input(loaded.error());
  }
  const petri::PnmlNet& pn = loaded.value();
  const bool tty = isatty(STDERR_FILENO) == 1;

  petri::ExploreOptions eo;
  eo.max_memory_bytes = o.max_memory_mb << 20;
  eo.liveness = !o.no_liveness;
  const auto start = std::chrono::steady_clock::now();
  g_interrupted = false;
  auto previous = std::signal(SIGINT, on_interrupt);
  eo.progress = [&](const petri::ExploreProgress& p) {
    if (tty) {
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::cerr << fmt::format("\r  {} states, {} explored, {} states/s, {} MB   ",
                               human(static_cast<double>(p.states)), human(static_cast<double>(p.explored)),
                               human(s > 0 ? static_cast<double>(p.states) / s : 0.0), p.memory_bytes >> 20)
                << std::flush;
    }
    return !g_interrupted.load();
  };
  petri::ExploreResult r = petri::explore(pn.net, eo);
  std::signal(SIGINT, previous);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (tty) std::cerr << "\r" << std::string(70, ' ') << "\r" << std::flush;

  if (o.format == "json") {
    nlohmann::ordered_json j;
    j["states"] = r.states;
    j["edges"] = r.edges;
    j["max_tokens_in_place"] = r.max_tokens_in_place;
    j["max_tokens_per_marking"] = r.max_tokens_per_marking;
    j["deadlock"] = r.deadlock;
    j["one_safe"] = r.one_safe;
    j["quasi_live"] = r.quasi_live;
    j["live"] = r.live.value_or(false);
    if (!r.complete || !r.live) {
      // A partial report: the values so far, and why it stopped.
      j["complete"] = r.complete;
      j["live_decided"] = r.live.has_value();
      if (!r.complete) j["stopped"] = r.stopped_why;
    }
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << fmt::format("{} ({}): {} places, {} transitions, {} arcs\n", pn.name, o.pnml, pn.net.place_count(),
                             pn.net.transition_count(), pn.net.arc_count());
    std::cout << fmt::format("  states                  {}\n", r.states);
    std::cout << fmt::format("  edges                   {}\n", r.edges);
    std::cout << fmt::format("  max tokens in a place   {}\n", r.max_tokens_in_place);
    std::cout << fmt::format("  max tokens per marking  {}\n", r.max_tokens_per_marking);
    std::cout << fmt::format("  deadlock                {}\n", yes_no(r.deadlock));
    std::cout << fmt::format("  1-safe                  {}\n", yes_no(r.one_safe));
    std::cout << fmt::format("  quasi-live              {}\n", yes_no(r.quasi_live));
    std::cout << fmt::format("  live                    {}\n", r.live ? yes_no(*r.live) : "not decided");
    std::cout << fmt::format("  explored in {:.3f} s ({} states/s), {:.1f} bytes/state ({} word{} per marking)\n",
                             seconds, human(seconds > 0 ? static_cast<double>(r.states) / seconds : 0.0),
                             r.states ? static_cast<double>(r.memory_bytes) / static_cast<double>(r.states) : 0.0,
                             r.words_per_state, r.words_per_state == 1 ? "" : "s");
    if (!r.complete) std::cout << "  PARTIAL: " << r.stopped_why << "\n";
  }
  return r.complete ? kExitOk : kExitAbort;
}

int run_verify_mission(const VerifyOptions& o) {
  if (!o.mission.ends_with(".coral")) {
    std::cerr << fmt::format(
        "strata verify: '{}' is not a CORAL mission (.coral); PROLOG rules are not nets (`strata run` checks them "
        "at load, docs/prolog.md), and a PNML net needs --pnml\n",
        o.mission);
    return kExitUsage;
  }
  auto catalogue = load_catalogue_option(o.catalogue);
  if (!catalogue) {
    std::cerr << "strata verify: " << catalogue.error().message << "\n";
    return exit_code_for_input(catalogue.error());
  }
  run::CoralLoad load = run::load_coral_file(o.mission, catalogue.value(), std::cerr, "strata verify");
  if (!load.program) return load.exit_code;
  coral::VerifyOptions vo;
  vo.max_states = o.max_states;
  const coral::VerifyReport report = coral::verify_program(*load.program, vo);
  if (o.format == "json") {
    std::cout << coral::verify_json(report).dump(2) << "\n";
  } else {
    std::cout << coral::verify_text(report);
  }
  return report.ok() ? kExitOk : kExitInvalid;
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
                  "MISSION: stop exploring a net after this many markings (its whole-graph properties are then "
                  "not decided)")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100'000'000}))
      ->capture_default_str();
  cmd->add_option("--format", o->format, "text or json")->check(CLI::IsMember({"text", "json"}))->capture_default_str();
  cmd->add_option(
         "--max-memory", o->max_memory_mb,
         "--pnml: stop with a partial report when the markings and their index would need more MB (0: no limit)")
      ->capture_default_str();
  cmd->add_flag("--no-liveness", o->no_liveness, "--pnml: skip the liveness pass (a second walk of the graph)");
  auto q = std::make_shared<QuestionFlags>();
  add_question_options(*cmd, *q);
  cmd->footer(
      "Exit, MISSION: 0 when every property of every net holds; 65 when one fails or is not decided, or the "
      "mission does not compile; 74 for a file it cannot open.\n"
      "Exit, --pnml: 0 when the graph was explored in full; 1 when a limit or Ctrl-C stopped it (a partial "
      "report); 65 for a net Strata cannot read; 74 for a file it cannot open.");
  return [o, q, cmd] {
    if (o->mission.empty() && o->pnml.empty()) {
      std::cerr << "strata verify: give a mission (.coral) or --pnml FILE\n";
      return static_cast<int>(kExitUsage);
    }
    if (question_requested(*q)) {
      const QuestionLimits limits{cmd->get_option("--max-states")->count() ? o->max_states : 0, o->max_memory_mb};
      return o->pnml.empty() ? run_mission_question(o->mission, o->catalogue, *q, o->format, limits)
                             : run_pnml_question(o->pnml, *q, o->format, limits);
    }
    return o->pnml.empty() ? run_verify_mission(*o) : run_verify_pnml(*o);
  };
}

}  // namespace strata::cli
