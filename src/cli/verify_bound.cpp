#include "cli/verify_bound.h"

#include <chrono>
#include <iostream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/run_problems.h"
#include "coral/timing.h"
#include "run/bound_options.h"
#include "run/coral_load.h"

namespace strata::cli {
namespace {

nlohmann::ordered_json steps_json(const std::vector<coral::BoundStep>& steps) {
  auto out = nlohmann::ordered_json::array();
  for (const auto& s : steps) {
    out.push_back({{"t_s", s.t_s ? nlohmann::ordered_json(*s.t_s) : nlohmann::ordered_json(nullptr)},
                   {"net", s.net},
                   {"what", s.what}});
  }
  return out;
}

std::string steps_text(const std::vector<coral::BoundStep>& steps, bool all) {
  std::string out;
  std::size_t first = 0;
  if (!all) {
    // Before the event: the last few steps, and how many there were.
    std::size_t before = 0;
    while (before < steps.size() && !steps[before].t_s) ++before;
    if (before > 4) {
      out += fmt::format("      ... {} steps before (-v shows them)\n", before - 4);
      first = before - 4;
    }
  }
  for (std::size_t i = first; i < steps.size(); ++i) {
    const auto& s = steps[i];
    const std::string t = s.t_s ? fmt::format("{:7.1f} s", *s.t_s) : std::string("   before");
    out += fmt::format("    {}  {}{}\n", t, s.net.empty() ? "" : s.net + ": ", s.what);
  }
  return out;
}

bool holds(const coral::BoundQuery& q, const coral::BoundAnswer& a) {
  if (a.verdict != coral::BoundAnswer::Verdict::Bounded) return false;
  return !q.within_s || a.worst_s <= *q.within_s + 1e-9;
}

}  // namespace

int run_mission_bounds(const std::string& mission, const std::string& catalogue_path, const BoundFlags& flags,
                       const std::string& format, std::uint64_t max_states, bool verbose) {
  const bool json = format == "json";
  std::vector<coral::BoundQuery> queries;
  for (const std::string& text : flags.questions) {
    auto q = coral::parse_bound(text);
    if (!q) {
      std::cerr << fmt::format("strata verify: --bound '{}': {}\n", text, q.error().message);
      return kExitUsage;
    }
    queries.push_back(std::move(q.value()));
  }
  auto catalogue = load_catalogue_option(catalogue_path);
  if (!catalogue) {
    std::cerr << "strata verify: " << catalogue.error().message << "\n";
    return exit_code_for_input(catalogue.error());
  }
  run::CoralLoad load = run::load_coral_file(mission, catalogue.value());
  if (int code = print_coral_load(std::cerr, load, "strata verify"); code != kExitOk) return code;
  if (!load.program->mission) {
    std::cerr << fmt::format("strata verify: {} declares no mission: --bound asks about a mission's run\n", mission);
    return kExitUsage;
  }
  const coral::BoundOptions bo = run::bound_options(catalogue.value(), flags.depth_max_m, max_states);
  int code = kExitOk;
  auto answers = nlohmann::ordered_json::array();
  for (const coral::BoundQuery& q : queries) {
    const auto start = std::chrono::steady_clock::now();
    const coral::BoundAnswer a = coral::analyse_bound(*load.program, q, bo);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (a.verdict == coral::BoundAnswer::Verdict::Unsupported) {
      std::cerr << fmt::format("strata verify: --bound '{}': {}\n", q.text, a.message);
      if (code == kExitOk) code = kExitUsage;
      continue;
    }
    const bool ok = holds(q, a);
    if (!ok) code = kExitInvalid;
    if (json) {
      nlohmann::ordered_json j{{"question", q.text}, {"verdict", coral::bound_verdict_name(a.verdict)}};
      const bool bounded = a.verdict == coral::BoundAnswer::Verdict::Bounded;
      j["worst_s"] = bounded ? nlohmann::ordered_json(a.worst_s) : nlohmann::ordered_json(nullptr);
      j["best_s"] = bounded ? nlohmann::ordered_json(a.best_s) : nlohmann::ordered_json(nullptr);
      j["within_s"] = q.within_s ? nlohmann::ordered_json(*q.within_s) : nlohmann::ordered_json(nullptr);
      j["holds"] = ok;
      if (q.to == coral::BoundQuery::To::Surface) j["ascent_s"] = bo.ascent_s;
      j["path"] = steps_json(a.path);
      j["cycle"] = steps_json(a.cycle);
      j["ends_without"] = a.ends_without;
      j["ends_without_path"] = steps_json(a.ends_without_path);
      if (!a.message.empty()) j["message"] = a.message;
      j["states"] = a.states;
      j["seconds"] = seconds;
      answers.push_back(std::move(j));
      continue;
    }
    std::string head;
    switch (a.verdict) {
      case coral::BoundAnswer::Verdict::Bounded:
        head = fmt::format("at worst {:.1f} s, at best {:.1f} s", a.worst_s, a.best_s);
        if (q.within_s)
          head +=
              ok ? fmt::format(": within {} s holds", *q.within_s) : fmt::format(": within {} s FAILS", *q.within_s);
        break;
      case coral::BoundAnswer::Verdict::Unbounded: head = "UNBOUNDED: " + a.message; break;
      case coral::BoundAnswer::Verdict::NoEvent: head = "the event never happens: " + a.message; break;
      case coral::BoundAnswer::Verdict::Unsupported: break;
    }
    std::cout << fmt::format("{}: {} ({} timed states, {:.2f} s)\n", q.text, head, a.states, seconds);
    if (!a.path.empty()) {
      std::cout << (a.verdict == coral::BoundAnswer::Verdict::Bounded ? "  the worst case:\n" : "  to the cycle:\n")
                << steps_text(a.path, verbose);
    }
    if (!a.cycle.empty()) std::cout << "  the cycle, which can repeat for ever:\n" << steps_text(a.cycle, true);
    if (q.to == coral::BoundQuery::To::Surface) {
      std::cout << fmt::format("  (the ascent from {} m is an estimate: {:.1f} s; --depth-max sets the depth)\n",
                               flags.depth_max_m, bo.ascent_s);
    }
    if (a.ends_without) {
      std::cout << "  note: a run can also end after the event without it:\n"
                << steps_text(a.ends_without_path, verbose);
    }
  }
  if (json) {
    nlohmann::ordered_json out{{"mission", mission}, {"bounds", answers}};
    std::cout << out.dump(2) << "\n";
  }
  return code;
}

}  // namespace strata::cli
