#include "coral/checker.h"

#include <algorithm>
#include <map>
#include <set>
#include <string_view>
#include <unordered_map>

#include <fmt/format.h>

#include "coral/arguments.h"
#include "coral/program.h"
#include "coral/timing.h"
#include "core/text.h"

namespace strata::coral {
namespace {

using core::DiagnosticKind;

struct NetRef {
  const ast::Net* net;
  const LoadedFile* file;
};

std::size_t expected_places(ast::TacticType type) {
  switch (type) {
    case ast::TacticType::Ask: return 2;
    case ast::TacticType::Exec:
    case ast::TacticType::Ood: return 1;
    default: return 0;
  }
}

std::string_view expected_places_text(ast::TacticType type) {
  switch (type) {
    case ast::TacticType::Ask: return "two places (true, then false)";
    case ast::TacticType::Exec: return "one place (marked when the function completes)";
    case ast::TacticType::Ood: return "one place (marked when the OOD is done)";
    default: return "no places";
  }
}

class NetChecker {
 public:
  NetChecker(const ast::Net& net, const std::unordered_map<std::string, NetRef>& library, core::DiagnosticSink& sink,
             const CheckOptions& options, ArgumentChecker& args)
      : net_(net), library_(library), sink_(sink), options_(options), args_(args) {}

  void run() {
    std::size_t errors_before = sink_.error_count();
    args_.check_params(net_);
    declare_places();
    check_data();
    std::map<std::string, const ast::Transition*> transitions;
    for (const auto& t : net_.transitions) {
      auto [it, fresh] = transitions.emplace(t.name.text, &t);
      if (!fresh) {
        auto* d = sink_.report(DiagnosticKind::DuplicateTransition, t.name.span,
                               fmt::format("transition '{}' is declared twice in '{}'", t.name.text, net_.name.text));
        core::add_note(d, it->second->name.span, "first declared here");
      }
      check_transition(t);
    }
    check_guards();
    // No warnings for a net with errors, nor once the sink stopped counting.
    if (sink_.error_count() == errors_before && !sink_.saturated()) warn_structure();
  }

 private:
  void declare_places() {
    for (const auto& p : net_.places) {
      auto [it, fresh] = places_.emplace(p.name.text, &p);
      if (!fresh) {
        auto* d = sink_.report(DiagnosticKind::DuplicatePlace, p.name.span,
                               fmt::format("place '{}' is declared twice in '{}'", p.name.text, net_.name.text));
        core::add_note(d, it->second->name.span, "first declared here");
      } else {
        place_names_.push_back(p.name.text);
      }
      if (p.is_exit && p.initial > 0) {
        sink_.report(DiagnosticKind::ExitHasInitialMark, p.initial_span,
                     fmt::format("exit place '{}' cannot hold an initial mark: the phase would end "
                                 "before it starts",
                                 p.name.text));
      }
    }
  }

  void check_data() {
    if (net_.kind == ast::Net::Kind::Phase) {
      for (const auto& d : net_.data) {
        sink_.report(DiagnosticKind::DataOutsideMission, d.span,
                     "a data file belongs to the mission, not to a phase net");
      }
    } else if (net_.data.size() > 1) {
      auto* d = sink_.report(DiagnosticKind::DuplicateData, net_.data[1].span,
                             fmt::format("mission '{}' names more than one data file", net_.name.text));
      core::add_note(d, net_.data[0].span, "first data file given here");
    }
  }

  // Returns the declaration, or reports UndefinedPlace.
  const ast::PlaceDecl* resolve(const ast::Name& n) {
    auto it = places_.find(n.text);
    if (it != places_.end()) return it->second;
    auto* d = sink_.report(DiagnosticKind::UndefinedPlace, n.span,
                           fmt::format("place '{}' is not declared in '{}'", n.text, net_.name.text));
    if (!d) return nullptr;  // past the error limit: spare the suggestion's cost
    if (auto s = core::suggest(n.text, place_names_)) core::add_note(d, fmt::format("did you mean '{}'?", *s));
    return nullptr;
  }

  void check_arcs(const std::vector<ast::ArcRef>& arcs, std::string_view clause) {
    std::map<std::string, const ast::ArcRef*> seen;
    for (const auto& a : arcs) {
      if (!resolve(a.place)) continue;
      auto [it, fresh] = seen.emplace(a.place.text, &a);
      if (!fresh) {
        auto* d = sink_.report(DiagnosticKind::DuplicateArc, a.span,
                               fmt::format("place '{}' appears twice in this {}; write it once "
                                           "with a weight ({}*N)",
                                           a.place.text, clause, a.place.text));
        core::add_note(d, it->second->span, "first listed here");
      }
    }
  }

  void check_transition(const ast::Transition& t) {
    check_arcs(t.waits, "wait");
    check_arcs(t.signals, "signal");
    for (const auto& action : t.actions) {
      if (const auto* tactic = std::get_if<ast::Tactic>(&action)) {
        check_tactic(*tactic);
      } else {
        check_phase(std::get<ast::Phase>(action));
      }
    }
  }

  void check_tactic(const ast::Tactic& a) {
    for (const auto& p : a.places) resolve(p);
    if (!a.type) return;
    std::size_t want = expected_places(*a.type);
    if (a.places.size() != want) {
      auto* d = sink_.report(DiagnosticKind::TacticArity, a.type_name.span,
                             fmt::format("TACTIC({}, ...) takes {}, but {} given", a.type_name.text,
                                         expected_places_text(*a.type), a.places.size()));
      if (a.type == ast::TacticType::Ask) {
        core::add_note(d, "ASK marks its first place when the predicate is true, its second when false");
      }
    }
    if (a.function) args_.check_names(net_, a.function->args);
    if (a.function && options_.primitive) check_primitive(a);
    if (a.text && a.text->kind == ast::Literal::Kind::Parameter) args_.check_report_param(net_, *a.text);
  }

  void check_primitive(const ast::Tactic& a) {
    const ast::Call& call = *a.function;
    auto sig = options_.primitive(call.name.text);
    if (!sig) {
      auto* d = sink_.report(DiagnosticKind::UnknownPrimitive, call.name.span,
                             fmt::format("unknown primitive '{}'", call.name.text));
      if (!d) return;
      if (auto s = core::suggest(call.name.text, options_.primitive_names)) {
        core::add_note(d, call.name.span, fmt::format("did you mean '{}'?", *s));
      }
      return;
    }
    if (sig->unavailable) {
      sink_.report(
          DiagnosticKind::PrimitiveUnavailable, call.name.span,
          fmt::format("'{}' is not available on {}: {}", call.name.text, options_.execution_level, *sig->unavailable));
    }
    if (sig->kind != a.type) {
      sink_.report(DiagnosticKind::TacticArguments, call.name.span,
                   fmt::format("'{}' is an {} primitive, not {}", call.name.text,
                               std::string(tactic_type_name(sig->kind)), a.type_name.text));
    }
    if (call.args.size() < sig->min_args || call.args.size() > sig->max_args) {
      sink_.report(DiagnosticKind::PrimitiveArity, call.span,
                   sig->min_args == sig->max_args
                       ? fmt::format("'{}' takes {} argument{}, but {} given", call.name.text, sig->min_args,
                                     sig->min_args == 1 ? "" : "s", call.args.size())
                       : fmt::format("'{}' takes {} to {} arguments, but {} given", call.name.text, sig->min_args,
                                     sig->max_args, call.args.size()));
    }
    args_.check_primitive_args(net_, call, *sig);
  }

  void check_phase(const ast::Phase& a) {
    for (const auto& p : a.places) resolve(p);
    args_.check_names(net_, a.args);
    auto it = library_.find(a.phase.text);
    if (it == library_.end()) {
      auto* d = sink_.report(DiagnosticKind::UnknownPhase, a.phase.span,
                             fmt::format("no phase net '{}' in the mission library", a.phase.text));
      if (!d) return;
      std::vector<std::string> phases;
      for (const auto& [name, ref] : library_) {
        if (ref.net->kind == ast::Net::Kind::Phase) phases.push_back(name);
      }
      std::sort(phases.begin(), phases.end());  // ties resolve the same way every run
      if (auto s = core::suggest(a.phase.text, phases))
        core::add_note(d, fmt::format("did you mean '{}'?", *s));
      else
        core::add_note(d, "import the file that declares it");
      return;
    }
    const ast::Net& phase = *it->second.net;
    if (phase.kind == ast::Net::Kind::Mission) {
      sink_.report(DiagnosticKind::PhaseIsMission, a.phase.span,
                   fmt::format("'{}' is a mission; PHASE runs a phase net", a.phase.text));
      return;
    }
    if (a.places.size() != phase.exits.size()) {
      auto* d = sink_.report(DiagnosticKind::PhaseArity, a.phase.span,
                             fmt::format("phase '{}' has {} exit(s), but PHASE gives {} place(s)", a.phase.text,
                                         phase.exits.size(), a.places.size()));
      std::string exits;
      for (const auto& e : phase.exits) exits += (exits.empty() ? "" : ", ") + e.text;
      core::add_note(
          d, phase.span,
          exits.empty() ? std::string("the phase declares no exit") : fmt::format("its exits, in order: {}", exits));
    }
    args_.check_phase_args(net_, a, phase);
  }

  // What expand_guards cannot say at its nodes: a name given twice, and a
  // handler that marks nothing (the net would be emptied and stall).
  void check_guards() {
    std::map<std::string, const ast::Guard*> seen;
    for (const auto& g : net_.guards) {
      auto [it, fresh] = seen.emplace(g.name.text, &g);
      if (!fresh) {
        auto* d = sink_.report(DiagnosticKind::DuplicateGuard, g.name.span,
                               fmt::format("guard '{}' is declared twice in '{}'", g.name.text, net_.name.text));
        core::add_note(d, it->second->name.span, "first declared here");
        continue;
      }
      bool marks = !g.signals.empty();
      for (const auto& action : g.actions) {
        const auto& places = std::holds_alternative<ast::Tactic>(action) ? std::get<ast::Tactic>(action).places
                                                                         : std::get<ast::Phase>(action).places;
        marks = marks || !places.empty();
      }
      if (!marks) {
        auto* d = sink_.report(DiagnosticKind::GuardHandlerMarksNothing, g.name.span,
                               fmt::format("guard '{}' marks no place when it trips: the net is emptied, so it "
                                           "would stall",
                                           g.name.text));
        core::add_note(d,
                       "give it a handler that ends the net: a PHASE whose exits map to places (an exit of "
                       "the net), or a signal");
      }
    }
  }

  // Warnings: transitions without input, places nothing touches,
  // transitions that no sequence of firings can ever enable, and parameters
  // nothing uses.
  void warn_structure() {
    std::set<std::string> read, written;
    for (const auto& t : net_.transitions) {
      // A guard's drops read every place: what they read says nothing of the net.
      if (!t.generated) {
        for (const auto& a : t.waits) read.insert(a.place.text);
      }
      for (const auto& a : t.signals) written.insert(a.place.text);
      for (const auto& action : t.actions) {
        const auto& places = std::holds_alternative<ast::Tactic>(action) ? std::get<ast::Tactic>(action).places
                                                                         : std::get<ast::Phase>(action).places;
        for (const auto& p : places) written.insert(p.text);
      }
      if (t.waits.empty()) {
        sink_.report(DiagnosticKind::NoInput, t.name.span,
                     fmt::format("transition '{}' waits for nothing, so it is always enabled and "
                                 "fires without end",
                                 t.name.text));
      }
    }
    for (const auto& p : net_.places) {
      if (places_.at(p.name.text) != &p || p.generated) continue;  // a duplicate, reported already
      if (p.is_exit) {
        if (!written.count(p.name.text)) {
          sink_.report(DiagnosticKind::ExitNeverMarked, p.name.span,
                       fmt::format("exit '{}' is never marked, so the phase never ends there", p.name.text));
        }
      } else if (!read.count(p.name.text) && !written.count(p.name.text)) {
        sink_.report(DiagnosticKind::UnusedPlace, p.name.span,
                     fmt::format("place '{}' is never read and never written", p.name.text));
      }
    }
    warn_never_enabled();
    warn_unused_params();
  }

  // A parameter that no primitive argument, REPORT or PHASE argument of the
  // net names: its value is given at every call and then dropped, most
  // likely a slip (`track(x0, y0, x1, y0)` for `y1`).
  void warn_unused_params() {
    if (net_.params.empty()) return;
    std::set<std::string_view> used;
    auto use = [&](const std::vector<ast::Literal>& args) {
      for (const auto& a : args) {
        if (a.kind == ast::Literal::Kind::Parameter) used.insert(a.text);
      }
    };
    for (const auto& t : net_.transitions) {
      for (const auto& action : t.actions) {
        if (const auto* tactic = std::get_if<ast::Tactic>(&action)) {
          if (tactic->function) use(tactic->function->args);
          if (tactic->text && tactic->text->kind == ast::Literal::Kind::Parameter) used.insert(tactic->text->text);
        } else {
          use(std::get<ast::Phase>(action).args);
        }
      }
    }
    for (const auto& p : net_.params) {
      if (used.count(p.name.text)) continue;
      sink_.report(DiagnosticKind::UnusedParameter, p.name.span,
                   fmt::format("parameter '{}' of '{}' is never used: every call gives it a value that is dropped",
                               p.name.text, net_.name.text));
    }
  }

  // Least fixpoint: a place may be marked if it starts marked or some
  // possibly-fireable transition writes it (by signal or action outcome); a
  // transition may fire if all its inputs may be marked. Weights are ignored,
  // so this over-approximates: what it calls dead is dead. A worklist over
  // each place's readers keeps it linear in the arcs, whatever the order of
  // declaration.
  void warn_never_enabled() {
    const auto& ts = net_.transitions;
    std::unordered_map<std::string_view, std::size_t> place_index;
    for (const auto& p : net_.places) place_index.emplace(p.name.text, place_index.size());
    std::vector<std::vector<std::size_t>> readers(place_index.size());
    std::vector<std::size_t> waiting(ts.size(), 0);  // distinct inputs not yet markable
    for (std::size_t i = 0; i < ts.size(); ++i) {
      std::set<std::size_t> inputs;
      for (const auto& a : ts[i].waits) {
        auto it = place_index.find(a.place.text);
        if (it != place_index.end()) inputs.insert(it->second);
      }
      waiting[i] = inputs.size();
      for (std::size_t p : inputs) readers[p].push_back(i);
    }
    std::vector<bool> markable(place_index.size(), false);
    std::vector<bool> can_fire(ts.size(), false);
    std::vector<std::size_t> work;  // transitions that became able to fire
    auto mark = [&](std::string_view name) {
      auto it = place_index.find(name);
      if (it == place_index.end()) return;
      std::size_t p = it->second;
      if (markable[p]) return;
      markable[p] = true;
      for (std::size_t t : readers[p]) {
        if (--waiting[t] == 0) work.push_back(t);
      }
    };
    for (std::size_t i = 0; i < ts.size(); ++i) {
      if (waiting[i] == 0) work.push_back(i);
    }
    for (const auto& p : net_.places) {
      if (p.initial > 0) mark(p.name.text);
    }
    while (!work.empty()) {
      std::size_t i = work.back();
      work.pop_back();
      if (can_fire[i]) continue;
      can_fire[i] = true;
      for (const auto& a : ts[i].signals) mark(a.place.text);
      for (const auto& action : ts[i].actions) {
        const auto& places = std::holds_alternative<ast::Tactic>(action) ? std::get<ast::Tactic>(action).places
                                                                         : std::get<ast::Phase>(action).places;
        for (const auto& p : places) mark(p.text);
      }
    }
    for (std::size_t i = 0; i < ts.size(); ++i) {
      const auto& t = ts[i];
      if (can_fire[i] || t.waits.empty() || t.generated) continue;
      auto* d = sink_.report(DiagnosticKind::NeverEnabled, t.name.span,
                             fmt::format("transition '{}' can never be enabled", t.name.text));
      for (const auto& a : t.waits) {
        auto it = place_index.find(a.place.text);
        if (it != place_index.end() && !markable[it->second]) {
          core::add_note(d, a.place.span, fmt::format("no firing can ever mark '{}'", a.place.text));
          break;
        }
      }
    }
  }

  const ast::Net& net_;
  const std::unordered_map<std::string, NetRef>& library_;
  core::DiagnosticSink& sink_;
  const CheckOptions& options_;
  ArgumentChecker& args_;
  std::unordered_map<std::string, const ast::PlaceDecl*> places_;
  std::vector<std::string> place_names_;
};

// A PHASE cycle would load phases without end: report the PHASE that closes
// it. Iterative depth-first search, so a long chain cannot overflow the stack.
void check_phase_recursion(const std::unordered_map<std::string, NetRef>& library, core::DiagnosticSink& sink) {
  enum class Mark { None, Active, Done };
  std::unordered_map<const ast::Net*, Mark> marks;
  std::vector<const ast::Net*> roots;
  roots.reserve(library.size());
  for (const auto& [name, ref] : library) roots.push_back(ref.net);
  std::sort(roots.begin(), roots.end(),
            [](const ast::Net* a, const ast::Net* b) { return a->name.text < b->name.text; });
  auto calls = [&](const ast::Net* net) {
    std::vector<const ast::Phase*> out;
    for (const auto& t : net->transitions) {
      for (const auto& action : t.actions) {
        if (const auto* phase = std::get_if<ast::Phase>(&action)) out.push_back(phase);
      }
    }
    return out;
  };
  struct Frame {
    const ast::Net* net;
    std::vector<const ast::Phase*> calls;
    std::size_t next = 0;
  };
  for (const ast::Net* root : roots) {
    if (marks[root] != Mark::None) continue;
    std::vector<Frame> stack;
    marks[root] = Mark::Active;
    stack.push_back({root, calls(root)});
    while (!stack.empty()) {
      Frame& f = stack.back();
      if (f.next == f.calls.size()) {
        marks[f.net] = Mark::Done;
        stack.pop_back();
        continue;
      }
      const ast::Phase* phase = f.calls[f.next++];
      auto it = library.find(phase->phase.text);
      if (it == library.end()) continue;
      const ast::Net* callee = it->second.net;
      if (callee->kind == ast::Net::Kind::Mission) continue;  // PhaseIsMission says it
      Mark m = marks[callee];
      if (m == Mark::Active) {
        sink.report(
            DiagnosticKind::PhaseRecursion, phase->phase.span,
            fmt::format("PHASE({}) in '{}' runs a phase that is already running", phase->phase.text, f.net->name.text));
      } else if (m == Mark::None) {
        marks[callee] = Mark::Active;
        stack.push_back({callee, calls(callee)});
      }
    }
  }
}

// A guard in a phase net that no chain of PHASE calls from the mission
// reaches never polls. (Without a mission, a file of phases for others to
// import, nothing is said.)
void warn_guards_never_active(const std::unordered_map<std::string, NetRef>& library, const ast::Net& mission,
                              core::DiagnosticSink& sink) {
  std::set<std::string> reached{mission.name.text};
  std::vector<const ast::Net*> work{&mission};
  while (!work.empty()) {
    const ast::Net* net = work.back();
    work.pop_back();
    for (const auto& t : net->transitions) {
      for (const auto& action : t.actions) {
        const auto* phase = std::get_if<ast::Phase>(&action);
        if (!phase || !reached.insert(phase->phase.text).second) continue;
        if (auto it = library.find(phase->phase.text); it != library.end()) work.push_back(it->second.net);
      }
    }
  }
  std::vector<const ast::Net*> unreached;
  for (const auto& [name, ref] : library) {
    if (!reached.count(name) && !ref.net->guards.empty()) unreached.push_back(ref.net);
  }
  std::sort(unreached.begin(), unreached.end(),
            [](const ast::Net* a, const ast::Net* b) { return a->name.text < b->name.text; });
  for (const ast::Net* net : unreached) {
    for (const auto& g : net->guards) {
      sink.report(DiagnosticKind::GuardNeverActive, g.name.span,
                  fmt::format("guard '{}' never polls: mission '{}' never runs phase '{}'", g.name.text,
                              mission.name.text, net->name.text));
    }
  }
}

// `require "...";`: a question `strata verify --bound` takes, with `within`,
// in the mission. Whether the mission has what it names is verify's to say.
void check_requirements(const ast::Net& net, core::DiagnosticSink& sink) {
  for (std::size_t i = 0; i < net.requirements.size(); ++i) {
    const auto& r = net.requirements[i];
    if (i == kMaxRequirements) {
      // Each is a timing analysis of the whole mission at every verification.
      sink.report(
          DiagnosticKind::BadRequirement, r.span,
          fmt::format("'{}' states more than {} requirements; merge or drop some", net.name.text, kMaxRequirements));
      break;
    }
    if (net.kind != ast::Net::Kind::Mission) {
      sink.report(
          DiagnosticKind::BadRequirement, r.span,
          fmt::format("a requirement is the mission's: '{}' is a phase net (move it to the mission)", net.name.text));
      continue;
    }
    auto q = parse_bound(r.value);
    if (!q) {
      sink.report(DiagnosticKind::BadRequirement, r.span, fmt::format("requirement: {}", q.error().message));
    } else if (!q.value().within_s) {
      sink.report(DiagnosticKind::BadRequirement, r.span,
                  "a requirement says how long at most: end it with `within S` (seconds)");
    }
  }
}

}  // namespace

void check(const Load& load, core::DiagnosticSink& sink, const CheckOptions& options) {
  std::unordered_map<std::string, NetRef> library;
  const ast::Net* mission = nullptr;
  for (const auto& file : load.files) {
    for (const auto& net : file.tree.nets) {
      auto [it, fresh] = library.emplace(net.name.text, NetRef{&net, &file});
      if (!fresh) {
        auto* d = sink.report(DiagnosticKind::DuplicateNet, net.name.span,
                              fmt::format("'{}' is declared twice in the mission library", net.name.text));
        core::add_note(d, it->second.net->name.span, "first declared here");
      }
      if (net.kind == ast::Net::Kind::Mission) {
        if (mission) {
          auto* d = sink.report(DiagnosticKind::MultipleMissions, net.name.span,
                                fmt::format("a load holds one mission, but '{}' is a second", net.name.text));
          core::add_note(d, mission->name.span, "the first mission");
        } else {
          mission = &net;
        }
      }
    }
  }
  NetLibrary nets;
  for (const auto& [name, ref] : library) nets.emplace(name, ref.net);
  ArgumentChecker args(nets, sink, options);
  for (const auto& file : load.files) {
    for (const auto& net : file.tree.nets) NetChecker(net, library, sink, options, args).run();
  }
  check_phase_recursion(library, sink);
  if (mission) warn_guards_never_active(library, *mission, sink);
  for (const auto& file : load.files) {
    for (const auto& net : file.tree.nets) check_requirements(net, sink);
  }
}

}  // namespace strata::coral
