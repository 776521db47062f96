#include "coral/guards.h"

#include <set>

#include <fmt/format.h>

namespace strata::coral {
namespace {

ast::Name guard_node_name(std::string text, const core::SourceSpan& span) { return ast::Name{std::move(text), span}; }

ast::ArcRef guard_arc(const std::string& place, const core::SourceSpan& span) {
  return ast::ArcRef{guard_node_name(place, span), 1, span};
}

ast::Tactic guard_tactic(ast::TacticType type, ast::Call call, std::vector<std::string> places,
                         const core::SourceSpan& span) {
  ast::Tactic t;
  t.type = type;
  t.type_name = guard_node_name(std::string(type == ast::TacticType::Ask ? "ASK" : "EXEC"), span);
  for (auto& p : places) t.places.push_back(guard_node_name(std::move(p), span));
  t.function = std::move(call);
  t.span = span;
  return t;
}

ast::Transition guard_transition(std::string name, int priority, const ast::Guard& g) {
  ast::Transition t;
  t.name = guard_node_name(std::move(name), g.name.span);
  t.priority = priority;
  t.span = g.span;
  t.extent = g.extent;
  t.generated = true;
  return t;
}

}  // namespace

std::string guard_term_text(const ast::GuardTerm& term) {
  std::string out = term.negated ? "not " + term.ask.name.text : term.ask.name.text;
  if (!term.ask.args.empty()) {
    out += '(';
    for (std::size_t i = 0; i < term.ask.args.size(); ++i) out += (i ? ", " : "") + term.ask.args[i].text;
    out += ')';
  }
  return out;
}

void expand_guards(ast::Net& net) {
  if (net.guards.empty()) return;
  std::set<std::string> seen;
  std::vector<const ast::Guard*> guards;
  for (const ast::Guard& g : net.guards) {
    if (seen.insert(g.name.text).second) guards.push_back(&g);
  }
  // Every guard's places first, so that each guard's drops reach the others'.
  for (const ast::Guard* g : guards) {
    auto add = [&](const std::string& suffix, std::uint32_t initial) {
      ast::PlaceDecl d;
      d.name = guard_node_name(fmt::format("{}.{}", g->name.text, suffix), g->name.span);
      d.initial = initial;
      d.generated = true;
      d.statement = g->span;
      net.places.push_back(std::move(d));
    };
    add("armed", 1);
    add("due", 0);
    for (std::size_t k = 2; k <= g->when.size(); ++k) add(fmt::format("term{}", k), 0);
    add("tripped", 0);
    add("cancel", 0);
  }
  const std::vector<ast::PlaceDecl> places = net.places;  // the drops' region: every place of the net
  for (const ast::Guard* g : guards) {
    const std::string& G = g->name.text;
    const std::string armed = G + ".armed", due = G + ".due", tripped = G + ".tripped", cancel = G + ".cancel";

    ast::Transition poll = guard_transition(G + ".poll", kGuardPollPriority, *g);
    poll.waits.push_back(guard_arc(armed, g->span));
    ast::Call sleep{guard_node_name("sleep", g->period.span), {g->period}, true, g->period.span};
    poll.actions.emplace_back(guard_tactic(ast::TacticType::Exec, std::move(sleep), {due}, g->period.span));
    net.transitions.push_back(std::move(poll));

    for (std::size_t k = 1; k <= g->when.size(); ++k) {
      const ast::GuardTerm& term = g->when[k - 1];
      ast::Transition ask = guard_transition(fmt::format("{}.ask{}", G, k), kGuardPollPriority, *g);
      ask.waits.push_back(guard_arc(k == 1 ? due : fmt::format("{}.term{}", G, k), term.span));
      const std::string go_on = k < g->when.size() ? fmt::format("{}.term{}", G, k + 1) : armed;
      std::vector<std::string> outcomes =
          term.negated ? std::vector<std::string>{go_on, tripped} : std::vector<std::string>{tripped, go_on};
      ask.actions.emplace_back(guard_tactic(ast::TacticType::Ask, term.ask, std::move(outcomes), term.span));
      net.transitions.push_back(std::move(ask));
    }

    ast::Transition trip = guard_transition(G + ".trip", kGuardTripPriority, *g);
    trip.waits.push_back(guard_arc(tripped, g->span));
    trip.signals.push_back(guard_arc(cancel, g->span));
    net.transitions.push_back(std::move(trip));

    // The region: every place of the net but its exits (never marked while
    // it runs) and this guard's own cycle (at tripped, which trip took).
    for (const ast::PlaceDecl& p : places) {
      if (p.is_exit || p.name.text == cancel) continue;
      if (p.generated && p.name.text.compare(0, G.size() + 1, G + ".") == 0) continue;
      ast::Transition drop = guard_transition(fmt::format("{}.drop.{}", G, p.name.text), kGuardDropPriority, *g);
      drop.waits.push_back(guard_arc(cancel, g->span));
      drop.waits.push_back(guard_arc(p.name.text, g->span));
      drop.signals.push_back(guard_arc(cancel, g->span));
      net.transitions.push_back(std::move(drop));
    }

    ast::Transition handle = guard_transition(G + ".handle", kGuardHandlePriority, *g);
    handle.waits.push_back(guard_arc(cancel, g->span));
    handle.actions = g->actions;
    handle.signals = g->signals;
    net.transitions.push_back(std::move(handle));
  }
}

}  // namespace strata::coral
