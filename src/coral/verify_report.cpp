#include "coral/verify_report.h"

#include <algorithm>

#include <fmt/format.h>

namespace strata::coral {
namespace {

nlohmann::ordered_json location_json(const Location& at) {
  nlohmann::ordered_json j{{"file", at.file}};
  if (at.line > 0) {
    j["line"] = at.line;
    j["col"] = at.col;
  }
  j[at.kind.empty() ? "net" : at.kind] = at.name;
  return j;
}

constexpr std::size_t kInvariantsShown = 8;
constexpr std::size_t kWidth = 100;

std::string join_items(const std::vector<std::string>& items, std::string_view sep = ", ") {
  std::string s;
  for (const auto& i : items) s += (s.empty() ? "" : std::string(sep)) + i;
  return s;
}

std::string counterexample_text(const Counterexample& cx, std::string_view indent) {
  std::string out;
  if (cx.steps.empty()) out += fmt::format("{}at the initial marking\n", indent);
  for (std::size_t i = 0; i < cx.steps.size(); ++i) {
    if (cx.repeat_from && *cx.repeat_from == i)
      out += fmt::format("{}   -- from here on the steps can repeat --\n", indent);
    out += fmt::format("{}{:>3}. {}\n", indent, i + 1, step_text(cx.steps[i]));
  }
  if (cx.timed) return out;  // across nets: no one marking to show
  out += fmt::format("{}marking: {}\n", indent, cx.marking);
  if (!cx.in_flight.empty()) out += fmt::format("{}in flight: {}\n", indent, join_items(cx.in_flight));
  return out;
}

// One property; its counterexample unless an earlier property of the same
// net printed the same one (`shown` keeps those, by text).
std::string property_line(const Property& p, std::vector<std::pair<std::string, std::string>>& shown) {
  const char* tag = p.status == Property::Status::Holds   ? "ok  "
                    : p.status == Property::Status::Fails ? (p.blocking ? "FAIL" : "warn")
                                                          : (p.blocking ? "??  " : "?   ");
  std::string out = fmt::format("  {}  {:<16} {}\n", tag, p.key, p.message);
  if (p.status != Property::Status::Holds && p.at.line > 0 && p.at.kind != "net") {
    out += fmt::format("        at {}:{}:{} ({} {})\n", p.at.file, p.at.line, p.at.col, p.at.kind, p.at.name);
  }
  if (!p.counterexample) return out;
  const Counterexample& cx = *p.counterexample;
  // A requirement's path is evidence for the studio; the text shows it
  // when the requirement fails.
  if (cx.timed && p.status == Property::Status::Holds) return out;
  std::string text = counterexample_text(cx, "        ");
  for (const auto& [key, earlier] : shown) {
    if (earlier == text) return out + fmt::format("        the same sequence as for {}\n", key);
  }
  shown.emplace_back(p.key, text);
  if (!cx.steps.empty()) {
    out += fmt::format("        {} ({} step{}):\n", cx.timed ? "the worst path" : "shortest sequence", cx.steps.size(),
                       cx.steps.size() == 1 ? "" : "s");
  }
  return out + text;
}

// "1 place", "2 places".
std::string count(std::uint64_t n, std::string_view one, std::string_view many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}

std::string net_heading(const NetVerification& n) {
  std::string out = fmt::format("{} {} ({}): {}, {}; analysis adds {}, {}\n", n.kind, n.name, n.file,
                                count(n.places, "place", "places"), count(n.transitions, "transition", "transitions"),
                                count(n.in_flight_places, "in-flight place", "in-flight places"),
                                count(n.outcomes, "outcome", "outcomes"));
  out += fmt::format("  {}, {}{}\n", count(n.states, "reachable marking", "reachable markings"),
                     count(n.edges, "edge", "edges"), n.complete ? "" : fmt::format(" (stopped: {})", n.stopped_why));
  return out;
}

std::string bounds_text(const NetVerification& n) {
  std::vector<std::string> other, never;
  for (const auto& b : n.bounds) {
    if (b.bound == 0)
      never.push_back(b.name);
    else if (b.bound != 1)
      other.push_back(fmt::format("{} {}", b.name, b.bound));
  }
  std::string out = fmt::format("  place bounds{}: ", n.complete ? "" : " (so far)");
  if (never.size() == n.bounds.size())
    out += "no place is marked";
  else if (other.empty())
    out += never.empty() ? "1 for every place" : "1 for every place marked";
  else
    out += fmt::format("1 except {}", join_items(other));
  if (!never.empty() && never.size() != n.bounds.size()) out += fmt::format("; never marked: {}", join_items(never));
  return out + "\n";
}

std::string invariants_text(const NetVerification& n) {
  if (!n.invariants_complete) return fmt::format("  P-invariants: skipped: {}\n", n.invariants_skipped);
  std::string cover = n.uncovered.empty() ? ", covering every place"
                      : n.uncovered.size() == n.bounds.size()
                          ? ""
                          : fmt::format("; not covered: {}", join_items(n.uncovered));
  std::string out = fmt::format("  P-invariants: {}{}\n",
                                count(n.invariants.size(), "minimal P-semiflow", "minimal P-semiflows"), cover);
  for (std::size_t i = 0; i < n.invariants.size() && i < kInvariantsShown; ++i) {
    const Invariant& inv = n.invariants[i];
    const bool all_ones =
        std::all_of(inv.weights.begin(), inv.weights.end(), [](const auto& w) { return w.second == 1; });
    if (all_ones && inv.weights.size() == n.bounds.size()) {
      out += fmt::format("    the tokens of all {} places add up to {}\n", inv.weights.size(), inv.constant);
      continue;
    }
    // "a + 2*b + c = 1", wrapped.
    std::string line = "   ";
    for (std::size_t k = 0; k < inv.weights.size(); ++k) {
      const auto& [place, w] = inv.weights[k];
      std::string term = fmt::format(" {}{}", k == 0 ? "" : "+ ", w == 1 ? place : fmt::format("{}*{}", w, place));
      if (line.size() + term.size() > kWidth && line.size() > 4) {
        out += line + "\n";
        line = "     ";
      }
      line += term;
    }
    out += fmt::format("{} = {}\n", line, inv.constant);
  }
  if (n.invariants.size() > kInvariantsShown) {
    out += fmt::format("    ... and {} more (--format json lists them all)\n", n.invariants.size() - kInvariantsShown);
  }
  return out;
}

std::string summary(const VerifyReport& r) {
  std::size_t failing = 0, warned = 0;
  for (const auto& n : r.nets) {
    failing += n.ok() ? 0 : 1;
    warned += n.ok() && !n.all_hold() ? 1 : 0;
  }
  const char* nets = r.nets.size() == 1 ? "" : "s";
  if (failing == 0 && warned == 0) return fmt::format("verified {} net{}: every property holds\n", r.nets.size(), nets);
  if (failing == 0) {
    return fmt::format("verified {} net{}: safe to run; {} with a warning (one_safe or no_dead)\n", r.nets.size(), nets,
                       warned);
  }
  return fmt::format("verified {} net{}: {} with a property that fails or is not decided and blocks a run\n",
                     r.nets.size(), nets, failing);
}

}  // namespace

std::string_view status_name(Property::Status status) {
  switch (status) {
    case Property::Status::Holds: return "holds";
    case Property::Status::Fails: return "fails";
    case Property::Status::Undecided: return "undecided";
  }
  return "?";
}

std::string step_text(const TraceStep& s) {
  // The timing analysis's steps: when (since the event) and in which net.
  std::string when;
  if (s.t_s) when = fmt::format("{:.1f} s: ", *s.t_s);
  if (!s.instance.empty()) when += s.instance + ": ";
  if (s.kind == TraceStep::Kind::Pass) return when + s.action;
  std::string marks = s.marks.empty() ? "" : fmt::format(" -> {}", join_items(s.marks));
  if (s.kind == TraceStep::Kind::Fire) {
    return fmt::format("{}fire {}{}{}", when, s.transition, s.actions.empty() ? "" : ": " + join_items(s.actions),
                       marks);
  }
  return fmt::format("{}{} ({}) answers {}{}", when, s.action, s.transition, s.answer, marks);
}

std::string verify_text(const VerifyReport& report, VerifyDetail detail) {
  std::string out;
  for (const auto& n : report.nets) {
    const bool fine = n.all_hold();
    if (fine && detail == VerifyDetail::Problems) continue;
    if (fine && detail == VerifyDetail::Nets) {
      out += fmt::format("{} {} ({}): {}, every property holds\n", n.kind, n.name, n.file,
                         count(n.states, "reachable marking", "reachable markings"));
      continue;
    }
    out += net_heading(n);
    std::vector<std::pair<std::string, std::string>> shown;
    for (const auto& p : n.properties) {
      if (detail == VerifyDetail::Full || p.status != Property::Status::Holds) out += property_line(p, shown);
    }
    std::vector<std::string> exits;
    for (std::size_t e = 0; e < n.exits.size(); ++e) {
      exits.push_back(n.exit_reachable[e] ? n.exits[e] : n.exits[e] + (n.complete ? " (never)" : " (not yet)"));
    }
    if (!exits.empty()) out += fmt::format("  exits reached{}: {}\n", n.complete ? "" : " (so far)", join_items(exits));
    out += bounds_text(n);
    out += invariants_text(n);
    out += '\n';
  }
  return out + summary(report);
}

std::string verify_failures_text(const VerifyReport& report) {
  std::string out;
  for (const auto& n : report.nets) {
    if (n.all_hold()) continue;
    out += net_heading(n);
    std::vector<std::pair<std::string, std::string>> shown;
    for (const auto& p : n.properties) {
      if (p.status != Property::Status::Holds) out += property_line(p, shown);
    }
  }
  return out + summary(report);
}

nlohmann::ordered_json verify_json(const VerifyReport& report) {
  nlohmann::ordered_json nets = nlohmann::ordered_json::array();
  for (const auto& n : report.nets) {
    nlohmann::ordered_json j;
    j["name"] = n.name;
    j["kind"] = n.kind;
    j["file"] = n.file;
    j["at"] = location_json(n.at);
    j["ok"] = n.ok();
    j["all_hold"] = n.all_hold();
    j["places"] = n.places;
    j["transitions"] = n.transitions;
    j["in_flight_places"] = n.in_flight_places;
    j["outcomes"] = n.outcomes;
    j["states"] = n.states;
    j["edges"] = n.edges;
    j["complete"] = n.complete;
    if (!n.complete) j["stopped"] = n.stopped_why;
    j["properties"] = nlohmann::ordered_json::array();
    for (const auto& p : n.properties) {
      nlohmann::ordered_json pj{{"key", p.key},
                                {"status", status_name(p.status)},
                                {"blocking", p.blocking},
                                {"at", location_json(p.at)},
                                {"message", p.message}};
      if (p.counterexample) {
        nlohmann::ordered_json steps = nlohmann::ordered_json::array();
        for (const auto& s : p.counterexample->steps) {
          nlohmann::ordered_json sj{{"kind", s.kind == TraceStep::Kind::Fire     ? "fire"
                                             : s.kind == TraceStep::Kind::Answer ? "answer"
                                                                                 : "pass"},
                                    {"transition", s.transition}};
          if (!s.instance.empty()) sj["instance"] = s.instance;
          if (!s.net.empty()) sj["net"] = s.net;
          if (s.t_s) sj["t_s"] = *s.t_s;
          if (s.kind == TraceStep::Kind::Fire) {
            sj["actions"] = s.actions;
          } else {
            sj["action"] = s.action;
            sj["answer"] = s.answer;
          }
          sj["marks"] = s.marks;
          sj["text"] = step_text(s);
          steps.push_back(std::move(sj));
        }
        nlohmann::ordered_json cj{
            {"steps", steps}, {"marking", p.counterexample->marking}, {"in_flight", p.counterexample->in_flight}};
        if (p.counterexample->repeat_from) cj["repeat_from"] = *p.counterexample->repeat_from;
        if (p.counterexample->timed) cj["timed"] = true;
        pj["counterexample"] = std::move(cj);
      }
      j["properties"].push_back(std::move(pj));
    }
    j["exits"] = nlohmann::ordered_json::array();
    for (std::size_t e = 0; e < n.exits.size(); ++e) {
      j["exits"].push_back({{"place", n.exits[e]}, {"reachable", static_cast<bool>(n.exit_reachable[e])}});
    }
    j["bounds"] = nlohmann::ordered_json::array();
    for (const auto& b : n.bounds) {
      j["bounds"].push_back(
          {{"place", b.name}, {"bound", b.bound}, {"in_flight", b.in_flight}, {"at", location_json(b.at)}});
    }
    j["invariants_complete"] = n.invariants_complete;
    if (!n.invariants_complete) j["invariants_skipped"] = n.invariants_skipped;
    j["invariants"] = nlohmann::ordered_json::array();
    for (const auto& inv : n.invariants) {
      nlohmann::ordered_json w = nlohmann::ordered_json::object();
      // The places of a semiflow are distinct: appended without ordered_json's
      // search for an existing key, which made a 200,000-place chain's one
      // semiflow quadratic (half a minute).
      auto& entries =
          static_cast<nlohmann::ordered_json::object_t::Container&>(w.get_ref<nlohmann::ordered_json::object_t&>());
      entries.reserve(inv.weights.size());
      for (const auto& [place, weight] : inv.weights) entries.emplace_back(place, weight);
      j["invariants"].push_back({{"weights", w}, {"constant", inv.constant}});
    }
    j["uncovered"] = n.uncovered;
    nets.push_back(std::move(j));
  }
  return {{"ok", report.ok()}, {"all_hold", report.all_hold()}, {"nets", nets}};
}

}  // namespace strata::coral
