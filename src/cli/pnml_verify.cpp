#include "cli/pnml_verify.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <iostream>
#include <new>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/validators.h"
#include "core/exit_codes.h"
#include "core/memory.h"
#include "petri/explorer.h"
#include "petri/pnml.h"

namespace strata::cli {
namespace {

std::string yes_no_text(bool b) { return b ? "yes" : "no"; }

std::chrono::steady_clock::time_point deadline_after(double seconds) {
  if (seconds <= 0) return std::chrono::steady_clock::time_point::max();
  return std::chrono::steady_clock::now() +
         std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
}

// A verdict that a partial exploration may not have settled: null in JSON.
// (Plain bools, not std::optional<bool>: GCC 12 at -O2 warns that an
// optional<bool> built by a conditional may be used uninitialized.)
struct Verdict {
  bool decided = false;
  bool value = false;
};
// A witness (a deadlock, two tokens, a transition fired) settles it as
// `if_witnessed`; a complete exploration without one settles it the other way.
Verdict settle(bool witnessed, bool if_witnessed, bool complete) {
  return witnessed ? Verdict{true, if_witnessed} : Verdict{complete, !if_witnessed};
}
nlohmann::ordered_json verdict(Verdict v) { return v.decided ? nlohmann::ordered_json(v.value) : nullptr; }
std::string verdict_text(Verdict v) { return v.decided ? yes_no_text(v.value) : "not decided"; }

std::atomic<bool> g_interrupted{false};
extern "C" void on_interrupt(int) { g_interrupted = true; }

std::string human(double n) {
  if (n >= 1e9) return fmt::format("{:.2f} G", n / 1e9);
  if (n >= 1e6) return fmt::format("{:.2f} M", n / 1e6);
  if (n >= 1e3) return fmt::format("{:.1f} k", n / 1e3);
  return fmt::format("{:.0f}", n);
}

}  // namespace

int run_verify_pnml(const PnmlVerifyOptions& o) {
  auto loaded = petri::read_pnml(o.path);
  if (!loaded) {
    std::cerr << o.who << ": " << loaded.error().message << "\n";
    return exit_code_for_input(loaded.error());
  }
  const petri::PnmlNet& pn = loaded.value();
  const bool tty = isatty(STDERR_FILENO) == 1;

  petri::ExploreOptions eo;
  // The limit is on the process: what it holds already (the net) counts.
  eo.max_memory_bytes = core::memory_left(o.max_memory_mb << 20);  // 0: none
  eo.max_states = o.max_states;
  eo.deadline = deadline_after(o.time_limit_s);
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

  // What a partial exploration settles: a witness found (a deadlock, two
  // tokens, every transition fired); the rest is not decided.
  const Verdict deadlock = settle(r.deadlock, true, r.complete);
  const Verdict one_safe = settle(!r.one_safe, false, r.complete);
  const Verdict quasi_live = settle(r.quasi_live, true, r.complete);
  if (o.format == "json") {
    nlohmann::ordered_json j;
    j["states"] = r.states;
    j["edges"] = r.edges;
    j["max_tokens_in_place"] = r.max_tokens_in_place;
    j["max_tokens_per_marking"] = r.max_tokens_per_marking;
    j["deadlock"] = verdict(deadlock);
    j["one_safe"] = verdict(one_safe);
    j["quasi_live"] = verdict(quasi_live);
    j["live"] = verdict(Verdict{r.live.has_value(), r.live.value_or(false)});
    if (!r.complete || !r.live) {
      // A partial report: the counts so far, null for what is not decided,
      // and why.
      j["complete"] = r.complete;
      j["live_decided"] = r.live.has_value();
      if (!r.complete) j["stopped"] = r.stopped_why;
      if (r.complete && !r.live) j["live_not_decided"] = r.live_why;
    }
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << fmt::format("{} ({}): {} places, {} transitions, {} arcs\n", pn.name, o.path, pn.net.place_count(),
                             pn.net.transition_count(), pn.net.arc_count());
    const char* so_far = r.complete ? "" : " (so far)";
    std::cout << fmt::format("  states                  {}{}\n", r.states, so_far);
    std::cout << fmt::format("  edges                   {}{}\n", r.edges, so_far);
    std::cout << fmt::format("  max tokens in a place   {}{}\n", r.max_tokens_in_place, so_far);
    std::cout << fmt::format("  max tokens per marking  {}{}\n", r.max_tokens_per_marking, so_far);
    std::cout << fmt::format("  deadlock                {}\n", verdict_text(deadlock));
    std::cout << fmt::format("  1-safe                  {}\n", verdict_text(one_safe));
    std::cout << fmt::format("  quasi-live              {}\n", verdict_text(quasi_live));
    std::cout << fmt::format("  live                    {}\n", r.live ? yes_no_text(*r.live)
                                                               : r.complete && !r.live_why.empty()
                                                                   ? "not decided: " + r.live_why
                                                                   : "not decided");
    std::cout << fmt::format("  explored in {:.3f} s ({} states/s), {:.1f} bytes/state ({} word{} per marking)\n",
                             seconds, human(seconds > 0 ? static_cast<double>(r.states) / seconds : 0.0),
                             r.states ? static_cast<double>(r.memory_bytes) / static_cast<double>(r.states) : 0.0,
                             r.words_per_state, r.words_per_state == 1 ? "" : "s");
    if (!r.complete) std::cout << "  PARTIAL: " << r.stopped_why << "\n";
  }
  // Ctrl-C in the liveness pass: the graph is whole, the report is not.
  return r.complete && !g_interrupted.load() ? kExitOk : kExitAbort;
}

const char* const kPnmlExitCodes =
    "Exit: 0 when the graph was explored in full (--question: when it was answered); 1 when a limit or Ctrl-C "
    "stopped it (a partial report; --question: not decided), or a replay stopped or did not reach a witness; 64 "
    "for a bad command line, question or sequence; 65 for a net Strata cannot read; 74 for a file it cannot open.";

PnmlCommandLine::PnmlCommandLine(const std::string& version)
    : app("strata-pnml: explore a place/transition net in PNML in full, or answer one question about it. The "
          "net is read from PNML (ISO/IEC 15909-2); the report gives its states and the Model Checking Contest's "
          "global properties (deadlock, 1-safe, quasi-live, live). This is `strata verify --pnml` in a program "
          "that loads nothing else (docs/verification.md)",
          "strata-pnml") {
  options.who = question.who = "strata-pnml";
  app.set_version_flag("--version", "strata-pnml " + version);
  app.add_option("net", options.path, "The net: a PNML file")
      ->required()
      ->check(CLI::Validator(
          [](const std::string& path) {
            return path.empty() ? std::string("an empty name names no file") : std::string();
          },
          "FILE"));
  app.add_option("--max-states", options.max_states,
                 "Stop exploring after this many markings (what needs the whole graph is then not decided; "
                 "default: no limit)")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100'000'000}));
  app.add_option("--format", options.format, "text or json")
      ->check(CLI::IsMember({"text", "json"}))
      ->capture_default_str();
  app.add_option("--max-memory", options.max_memory_mb,
                 "Stop before the process would hold more than this many MB (what is not settled is then not "
                 "decided; 0: no limit)")
      ->check(CLI::Range(std::size_t{0}, kMaxMemoryMb))
      ->capture_default_str();
  app.add_option("--time-limit", options.time_limit_s,
                 "Stop after this many seconds (what is not settled is then not decided; 0: none)")
      ->check(finite_range(0.0, 1e9))
      ->capture_default_str();
  app.add_flag("--no-liveness", options.no_liveness, "Skip the liveness pass (a second walk of the graph)");
  add_question_options(app, question, false);
  app.footer(kPnmlExitCodes);
}

int run_pnml_command(PnmlCommandLine& line) {
  const PnmlVerifyOptions& o = line.options;
  try {
    if (!question_requested(line.question)) return run_verify_pnml(o);
    return run_pnml_question(o.path, line.question, o.format,
                             QuestionLimits{o.max_states, o.max_memory_mb, o.time_limit_s});
  } catch (const std::bad_alloc&) {
    // Each analysis step catches its own; this is reading the net.
    std::cerr << o.who << ": out of memory before the analysis could start; nothing decided\n";
    return kExitAbort;
  }
}

}  // namespace strata::cli
