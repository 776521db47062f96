#include "coral/verifier.h"

#include <algorithm>
#include <chrono>
#include <functional>
#include <new>
#include <optional>
#include <string_view>

#include <fmt/format.h>

#include "coral/verifier_internal.h"
#include "petri/invariants.h"

namespace strata::coral {
namespace {

// A property decided within the limits: Undecided when the time is up
// before it starts or the memory runs out while it works.
template <class Decide>
Property within_limits(std::string key, const detail::StepLimits& limits, bool blocking, Decide decide) {
  Property p;
  if (limits.past_deadline()) {
    p.status = Property::Status::Undecided;
    p.message = "not decided: the time limit passed before this step";
  } else {
    try {
      p = decide();
    } catch (const std::bad_alloc&) {
      p = Property{};
      p.status = Property::Status::Undecided;
      p.message = "not decided: out of memory";
    }
  }
  p.key = std::move(key);
  p.blocking = blocking;
  return p;
}

// Explores one net and reports on it.
class NetVerifier {
 public:
  NetVerifier(const Program& program, const CompiledNet& cn, const std::vector<PhaseExits>& known,
              const detail::StepLimits& limits, const core::SourceManager* sources)
      : program_(program), cn_(cn), known_(known), limits_(limits), sources_(sources) {}

  NetVerification run() {
    const CompiledNet& cn = cn_;
    NetVerification v;
    v.name = cn.name;
    v.kind = cn.kind == ast::Net::Kind::Mission ? "mission" : "phase";
    v.file = cn.source_file;
    v.at = locate(cn.span, "net", cn.name);
    v.places = cn.net.place_count();
    v.transitions = cn.net.transition_count();
    std::optional<detail::ExploredNet> explored;
    try {
      explored.emplace(program_, cn, known_, limits_);
    } catch (const std::bad_alloc&) {
      explored.reset();
    }
    if (!explored) return out_of_memory(std::move(v));
    const detail::ExploredNet& x = *explored;
    const AnalysisNet& an = x.an;
    const petri::ReachGraph& g = x.graph;
    v.in_flight_places = an.net.place_count() - v.places;
    v.outcomes = an.net.transition_count() - v.transitions;
    v.states = g.state_count();
    v.edges = g.edge_count();
    v.complete = g.complete();
    v.stopped_why = g.stopped_why();

    const std::vector<std::uint64_t>& bounds = x.bounds;
    for (petri::PlaceId p = 0; p < an.net.place_count(); ++p) {
      v.bounds.push_back(
          {place_location(an, p), std::string(an.net.place_name(p)), bounds[p], !an.places[p].place.has_value()});
    }
    for (std::size_t e = 0; e < cn.exits.size(); ++e) {
      v.exits.emplace_back(cn.net.place_name(cn.exits[e]));
      v.exit_reachable.push_back(bounds[cn.exits[e]] > 0);
    }

    auto add = [&](std::string key, bool blocking, Property (*decide)(const detail::ExploredNet&)) {
      v.properties.push_back(within_limits(std::move(key), limits_, blocking, [&] { return decide(x); }));
    };
    add("bounded", true, detail::bounded);
    add("one_safe", false, detail::one_safe);
    add("no_dead", false, detail::no_dead);
    add("no_deadlock", true, detail::no_deadlock);
    add("can_always_end", true, detail::can_always_end);
    add("no_busy_cycle", true, detail::no_busy_cycle);
    add("exits_exclusive", true, detail::exits_exclusive);
    if (!cn.guards.empty()) {
      add("guards_can_trip", true, detail::guards_can_trip);
      add("handlers_end", true, detail::guard_handlers_end);
    }
    v.properties.push_back(
        within_limits("phase_depth", limits_, true, [&] { return detail::phase_depth(program_, cn); }));

    for (Property& p : v.properties) {
      if (p.about == Property::About::Place && p.about_id < an.net.place_count()) {
        p.at = place_location(an, p.about_id);
      } else if (p.about == Property::About::Transition && p.about_id < cn.net.transition_count()) {
        p.at = transition_location(p.about_id);
      } else {
        p.at = v.at;
      }
    }
    invariants(an.net, v);
    return v;
  }

 private:
  // The graph could not even be built: every property not decided.
  NetVerification out_of_memory(NetVerification v) const {
    v.complete = false;
    v.stopped_why = "out of memory";
    for (const char* key :
         {"bounded", "one_safe", "no_dead", "no_deadlock", "can_always_end", "no_busy_cycle", "exits_exclusive"}) {
      Property p;
      p.key = key;
      p.blocking = std::string_view(key) != "one_safe" && std::string_view(key) != "no_dead";
      p.status = Property::Status::Undecided;
      p.message = "not decided: out of memory";
      v.properties.push_back(std::move(p));
    }
    v.properties.push_back(
        within_limits("phase_depth", limits_, true, [&] { return detail::phase_depth(program_, cn_); }));
    v.invariants_complete = false;
    v.invariants_skipped = "out of memory";
    for (Property& p : v.properties) p.at = v.at;
    return v;
  }

  Location locate(const core::SourceSpan& span, std::string kind, std::string_view name) const {
    Location at;
    at.file = cn_.source_file;
    at.kind = std::move(kind);
    at.name = name;
    if (sources_ && span.file < sources_->size()) {
      at.file = sources_->path(span.file);
      const core::LineCol lc = sources_->line_col(span.file, span.offset);
      at.line = lc.line;
      at.col = lc.col;
    }
    return at;
  }

  Location transition_location(petri::TransitionId t) const {
    const core::SourceSpan span = t < cn_.transition_spans.size() ? cn_.transition_spans[t] : cn_.span;
    return locate(span, "transition", cn_.net.transition_name(t));
  }

  // A mission place where it is declared; an in-flight place at the
  // transition whose action it waits for.
  Location place_location(const AnalysisNet& an, petri::PlaceId p) const {
    const auto& origin = an.places[p];
    if (!origin.place) return transition_location(origin.transition);
    const core::SourceSpan span = *origin.place < cn_.place_spans.size() ? cn_.place_spans[*origin.place] : cn_.span;
    return locate(span, "place", cn_.net.place_name(*origin.place));
  }

  void invariants(const petri::Net& net, NetVerification& v) const {
    petri::SemiflowLimits sl;
    sl.max_memory_bytes = limits_.memory_for_step();
    sl.deadline = limits_.deadline;
    petri::Semiflows flows;
    try {
      flows = petri::p_semiflows(net, sl);
    } catch (const std::bad_alloc&) {
      flows = petri::Semiflows{};
      flows.complete = false;
      flows.stopped_why = "out of memory";
    }
    v.invariants_complete = flows.complete;
    v.invariants_skipped = flows.stopped_why;
    for (const auto& f : flows.flows) {
      Invariant inv;
      inv.constant = f.constant;
      for (auto [p, w] : f.weights) inv.weights.emplace_back(std::string(net.place_name(p)), w);
      v.invariants.push_back(std::move(inv));
    }
    if (flows.complete) {
      for (petri::PlaceId p = 0; p < net.place_count(); ++p) {
        if (!flows.covered[p]) v.uncovered.emplace_back(net.place_name(p));
      }
    }
  }

  const Program& program_;
  const CompiledNet& cn_;
  const std::vector<PhaseExits>& known_;
  const detail::StepLimits& limits_;
  const core::SourceManager* sources_;
};

}  // namespace

namespace detail {

std::vector<std::size_t> callees_first(const Program& program, std::optional<std::size_t> root) {
  std::vector<int> state(program.nets.size(), 0);  // 0 new, 1 on the path, 2 done
  std::vector<std::size_t> order;
  std::function<void(std::size_t)> visit = [&](std::size_t i) {
    state[i] = 1;
    for (const auto& actions : program.nets[i].actions) {
      for (const auto& a : actions) {
        if (a.kind != ActionSpec::Kind::Phase) continue;
        for (std::size_t j = 0; j < program.nets.size(); ++j) {
          if (program.nets[j].name == a.target && state[j] == 0) visit(j);
        }
      }
    }
    state[i] = 2;
    order.push_back(i);
  };
  if (root) {
    visit(*root);
    return order;
  }
  for (std::size_t i = 0; i < program.nets.size(); ++i) {
    if (state[i] == 0) visit(i);
  }
  return order;
}

}  // namespace detail

bool NetVerification::ok() const {
  return std::all_of(properties.begin(), properties.end(),
                     [](const Property& p) { return !p.blocking || p.status == Property::Status::Holds; });
}

bool NetVerification::all_hold() const {
  return std::all_of(properties.begin(), properties.end(),
                     [](const Property& p) { return p.status == Property::Status::Holds; });
}

bool VerifyReport::ok() const {
  return std::all_of(nets.begin(), nets.end(), [](const NetVerification& n) { return n.ok(); });
}

bool VerifyReport::all_hold() const {
  return std::all_of(nets.begin(), nets.end(), [](const NetVerification& n) { return n.all_hold(); });
}

namespace {

// One blocking property "requirement" per `require` of the mission: its
// question answered by the timing analysis (coral/timing.h) and held to its
// `within`.
void add_requirements(const Program& program, const CompiledNet& mission, const VerifyOptions& options,
                      NetVerification& v) {
  for (const auto& r : mission.requirements) {
    Property p;
    p.key = "requirement";
    p.at = v.at;
    if (options.sources && r.span.file < options.sources->size()) {
      p.at.file = options.sources->path(r.span.file);
      const core::LineCol lc = options.sources->line_col(r.span.file, r.span.offset);
      p.at.line = lc.line;
      p.at.col = lc.col;
    }
    auto q = parse_bound(r.text);
    if (!q || !q.value().within_s) {
      p.status = Property::Status::Fails;
      p.message = fmt::format("'{}' is no requirement (strata check says why)", r.text);
    } else if (!options.timing) {
      p.status = Property::Status::Undecided;
      p.message = fmt::format("{}: not decided (no vehicle timing given)", r.text);
    } else {
      const BoundAnswer a = analyse_bound(program, q.value(), *options.timing);
      const double within = *q.value().within_s;
      // The evidence, held or not: the worst path, or the way to the cycle
      // that delays TO for ever (the studio plays it on the nets).
      if (a.verdict == BoundAnswer::Verdict::Bounded || a.verdict == BoundAnswer::Verdict::Unbounded) {
        Counterexample cx;
        cx.timed = true;
        for (const BoundStep& b : a.path) cx.steps.push_back(b.trace);
        if (a.verdict == BoundAnswer::Verdict::Unbounded) {
          cx.repeat_from = cx.steps.size();
          for (const BoundStep& b : a.cycle) cx.steps.push_back(b.trace);
        }
        p.counterexample = std::move(cx);
      }
      switch (a.verdict) {
        case BoundAnswer::Verdict::Bounded:
          p.status = a.worst_s <= within + 1e-9 ? Property::Status::Holds : Property::Status::Fails;
          p.message = fmt::format("{}: at worst {:.1f} s{}", r.text, a.worst_s,
                                  p.status == Property::Status::Holds ? "" : fmt::format(", past {} s", within));
          break;
        case BoundAnswer::Verdict::Unbounded:
          p.status = Property::Status::Fails;
          p.message = fmt::format("{}: unbounded: {}", r.text, a.message);
          break;
        case BoundAnswer::Verdict::NoEvent:
          p.status = Property::Status::Holds;
          p.message = fmt::format("{}: the event never happens", r.text);
          break;
        case BoundAnswer::Verdict::Unsupported:
          p.status = Property::Status::Fails;
          p.message = fmt::format("{}: {}", r.text, a.message);
          break;
      }
    }
    v.properties.push_back(std::move(p));
  }
}

}  // namespace

VerifyReport verify_program(const Program& program, const VerifyOptions& options) {
  VerifyReport report;
  std::vector<PhaseExits> known;
  detail::StepLimits limits;
  limits.max_states = options.max_states;
  limits.max_memory_bytes = options.max_memory_bytes;
  if (options.time_limit_s > 0) {
    limits.deadline =
        std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                               std::chrono::duration<double>(options.time_limit_s));
  }
  for (std::size_t i : detail::callees_first(program, options.mission_only ? program.mission : std::nullopt)) {
    const CompiledNet& cn = program.nets[i];
    NetVerification v = NetVerifier(program, cn, known, limits, options.sources).run();
    if (v.complete) known.push_back({cn.name, v.exit_reachable});
    if (cn.kind == ast::Net::Kind::Mission) add_requirements(program, cn, options, v);
    report.nets.push_back(std::move(v));
  }
  return report;
}

std::vector<PhaseExits> reachable_phase_exits(const VerifyReport& report) {
  std::vector<PhaseExits> known;
  for (const auto& n : report.nets) {
    if (n.complete && n.kind == "phase") known.push_back({n.name, n.exit_reachable});
  }
  return known;
}

}  // namespace strata::coral
