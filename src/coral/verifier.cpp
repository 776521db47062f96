#include "coral/verifier.h"

#include <algorithm>
#include <functional>

#include "coral/verifier_internal.h"
#include "petri/invariants.h"

namespace strata::coral {
namespace {

// Explores one net and reports on it.
class NetVerifier {
 public:
  NetVerifier(const Program& program, const CompiledNet& cn, const std::vector<PhaseExits>& known,
              const VerifyOptions& options)
      : x_(program, cn, known, options) {}

  NetVerification run() {
    const CompiledNet& cn = x_.cn;
    const AnalysisNet& an = x_.an;
    const petri::ReachGraph& g = x_.graph;
    NetVerification v;
    v.name = cn.name;
    v.kind = cn.kind == ast::Net::Kind::Mission ? "mission" : "phase";
    v.file = cn.source_file;
    v.places = cn.net.place_count();
    v.transitions = cn.net.transition_count();
    v.in_flight_places = an.net.place_count() - v.places;
    v.outcomes = an.net.transition_count() - v.transitions;
    v.states = g.state_count();
    v.edges = g.edge_count();
    v.complete = g.complete();
    v.stopped_why = g.stopped_why();

    const std::vector<std::uint64_t>& bounds = x_.bounds;
    for (petri::PlaceId p = 0; p < an.net.place_count(); ++p) {
      v.bounds.push_back({std::string(an.net.place_name(p)), bounds[p], !an.places[p].place.has_value()});
    }
    for (std::size_t e = 0; e < cn.exits.size(); ++e) {
      v.exits.emplace_back(cn.net.place_name(cn.exits[e]));
      v.exit_reachable.push_back(bounds[cn.exits[e]] > 0);
    }

    v.properties.push_back(detail::bounded(x_));
    v.properties.push_back(detail::one_safe(x_));
    v.properties.push_back(detail::no_dead(x_));
    v.properties.push_back(detail::no_deadlock(x_));
    v.properties.push_back(detail::can_always_end(x_));
    v.properties.push_back(detail::no_busy_cycle(x_));
    v.properties.push_back(detail::exits_exclusive(x_));

    petri::Semiflows flows = petri::p_semiflows(an.net);
    v.invariants_complete = flows.complete;
    for (const auto& f : flows.flows) {
      Invariant inv;
      inv.constant = f.constant;
      for (auto [p, w] : f.weights) inv.weights.emplace_back(std::string(an.net.place_name(p)), w);
      v.invariants.push_back(std::move(inv));
    }
    if (flows.complete) {
      for (petri::PlaceId p = 0; p < an.net.place_count(); ++p) {
        if (!flows.covered[p]) v.uncovered.emplace_back(an.net.place_name(p));
      }
    }
    return v;
  }

 private:
  detail::ExploredNet x_;
};

// Nets in an order that puts every phase before the nets that call it (a
// cycle of PHASE calls, which the checker reports, is cut where found).
std::vector<std::size_t> callee_first(const Program& program, bool mission_only) {
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
  if (mission_only && program.mission) {
    visit(*program.mission);
    return order;
  }
  for (std::size_t i = 0; i < program.nets.size(); ++i) {
    if (state[i] == 0) visit(i);
  }
  return order;
}

}  // namespace

bool NetVerification::ok() const {
  return std::all_of(properties.begin(), properties.end(),
                     [](const Property& p) { return p.status == Property::Status::Holds; });
}

bool VerifyReport::ok() const {
  return std::all_of(nets.begin(), nets.end(), [](const NetVerification& n) { return n.ok(); });
}

VerifyReport verify_program(const Program& program, const VerifyOptions& options) {
  VerifyReport report;
  std::vector<PhaseExits> known;
  for (std::size_t i : callee_first(program, options.mission_only)) {
    const CompiledNet& cn = program.nets[i];
    NetVerification v = NetVerifier(program, cn, known, options).run();
    if (v.complete) known.push_back({cn.name, v.exit_reachable});
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
