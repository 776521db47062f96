// The timing analysis's model (coral/timing.h): the mission's analysis net
// with every PHASE call replaced by a copy of its phase, parameters bound,
// and what each transition means to the question.
#include <unordered_map>

#include <fmt/format.h>

#include "coral/timing_internal.h"

namespace strata::coral::timing_detail {
namespace {

std::optional<ast::Literal> resolve(const ast::Literal& l, const Inst& inst) {
  if (l.kind != ast::Literal::Kind::Parameter) return l;
  for (std::size_t i = 0; i < inst.cn->params.size() && i < inst.args.size(); ++i) {
    if (inst.cn->params[i].name.text == l.text) return inst.args[i];
  }
  return std::nullopt;
}

class Builder {
 public:
  Builder(const Program& p, const BoundOptions& o, Model& m) : program_(p), options_(o), m_(m) {}

  std::optional<std::string> add(const CompiledNet& cn, std::vector<ast::Literal> args, std::string path,
                                 std::size_t depth) {
    if (depth > kMaxPhaseDepth) return fmt::format("phases nest deeper than {} at {}", kMaxPhaseDepth, path);
    const std::uint32_t idx = static_cast<std::uint32_t>(m_.insts.size());
    m_.insts.push_back({});
    {
      Inst& inst = m_.insts[idx];
      inst.cn = &cn;
      inst.an = build_analysis_net(program_, cn);
      inst.args = std::move(args);
      inst.path = std::move(path);
      inst.place0 = m_.places;
      const std::size_t n = inst.an.net.place_count();
      inst.child.assign(n, -1);
      inst.lo.assign(n, -1);
      inst.hi.assign(n, -1);
      m_.places += static_cast<std::uint32_t>(n);
    }
    const std::size_t n = m_.insts[idx].an.net.place_count();
    std::unordered_map<std::string, int> calls;
    for (PlaceId pl = 0; pl < n; ++pl) {
      const AnalysisNet::PlaceOrigin origin = m_.insts[idx].an.places[pl];
      if (origin.place) continue;
      const ActionSpec& a = cn.actions[origin.transition][origin.action];
      if (a.kind == ActionSpec::Kind::Phase) {
        const CompiledNet* phase = program_.find(a.target);
        if (!phase) return fmt::format("{}: no phase net {}", m_.insts[idx].path, a.target);
        std::vector<ast::Literal> call_args;
        for (const ast::Literal& l : a.args) {
          auto v = resolve(l, m_.insts[idx]);
          if (!v) return fmt::format("{}: parameter {} has no value", m_.insts[idx].path, l.text);
          call_args.push_back(*v);
        }
        const int k = ++calls[a.target];
        std::string child_path = fmt::format("{}/{}#{}", m_.insts[idx].path, a.target, k);
        const auto child = static_cast<int>(m_.insts.size());
        if (auto e = add(*phase, std::move(call_args), std::move(child_path), depth + 1)) return e;
        m_.insts[idx].child[pl] = child;
        continue;
      }
      auto timing = options_.primitive ? options_.primitive(a.target) : std::nullopt;
      if (!timing) return fmt::format("the catalogue has no primitive {} (called in {})", a.target, cn.name);
      double lo = 0;
      double hi = timing->reply_s;
      if (timing->wait_arg) {
        double wait = timing->wait_arg_max;
        if (*timing->wait_arg < a.args.size()) {
          auto v = resolve(a.args[*timing->wait_arg], m_.insts[idx]);
          if (v) wait = number_value(*v).value_or(wait);
        }
        lo = wait;
        hi = wait + timing->reply_s;
      }
      const double tick = options_.tick_s;
      m_.insts[idx].lo[pl] = static_cast<int>(std::floor(lo / tick + 1e-9));
      m_.insts[idx].hi[pl] = static_cast<int>(std::ceil(hi / tick - 1e-9));
    }
    m_.insts[idx].end_place = m_.places;
    m_.insts[idx].end_inst = static_cast<std::uint32_t>(m_.insts.size());
    return std::nullopt;
  }

 private:
  const Program& program_;
  const BoundOptions& options_;
  Model& m_;
};

bool matches_to(const ActionSpec& a, const BoundQuery& q) {
  if (q.to != BoundQuery::To::Call && q.to != BoundQuery::To::Surface) return false;
  if (a.kind != ActionSpec::Kind::Tactic) return false;
  if (q.to == BoundQuery::To::Surface) return a.tactic == ast::TacticType::Exec && a.target == "surface";
  return a.target == q.to_name && (!q.to_verb || *q.to_verb == a.tactic);
}

std::optional<std::string> finish_model(Model& m, const BoundQuery& q) {
  m.lo.assign(m.places, -1);
  m.hi.assign(m.places, -1);
  m.child.assign(m.places, -1);
  bool event_seen = false;
  bool to_seen = false;
  for (std::uint32_t i = 0; i < m.insts.size(); ++i) {
    const Inst& inst = m.insts[i];
    for (PlaceId pl = 0; pl < inst.an.net.place_count(); ++pl) {
      m.lo[inst.place0 + pl] = inst.lo[pl];
      m.hi[inst.place0 + pl] = inst.hi[pl];
      m.child[inst.place0 + pl] = inst.child[pl];
      if (inst.lo[pl] >= 0) m.timed_places.push_back(inst.place0 + pl);
    }
    for (TransitionId t = 0; t < inst.an.net.transition_count(); ++t) {
      const AnalysisNet::Step& st = inst.an.steps[t];
      GlobalTransition g;
      g.inst = i;
      g.t = t;
      if (st.kind == AnalysisNet::Step::Kind::Outcome) {
        const ActionSpec& a = inst.cn->actions[st.transition][st.action];
        if (a.kind == ActionSpec::Kind::Phase) {
          const PlaceId flight = inst.an.net.inputs(t)[0].node;
          const Inst& child = m.insts[static_cast<std::size_t>(inst.child[flight])];
          g.child_exit = child.place0 + child.cn->exits.at(st.answer);
        } else {
          g.timed = true;
          if (q.from == BoundQuery::From::Fault && a.tactic == ast::TacticType::Ask && a.target == q.from_name) {
            g.ask_answer = st.answer == 0 ? 1 : 0;
            event_seen = true;
          }
        }
      } else if (st.kind == AnalysisNet::Step::Kind::Transition) {
        for (const ActionSpec& a : inst.cn->actions[st.transition]) {
          g.is_to = g.is_to || matches_to(a, q);
          if (q.from == BoundQuery::From::Start && a.kind == ActionSpec::Kind::Phase && a.target == q.from_name) {
            g.is_event = true;
          }
        }
        const GuardNode node = inst.cn->guard_node(st.transition);
        if (q.from == BoundQuery::From::Trip && node.role == GuardRole::Trip &&
            inst.cn->guards[node.guard].name == q.from_name) {
          g.is_event = true;
        }
        to_seen = to_seen || g.is_to;
        event_seen = event_seen || g.is_event;
      }
      m.transitions.push_back(g);
    }
  }
  m.consumers.assign(m.places, {});
  for (std::uint32_t k = 0; k < m.transitions.size(); ++k) {
    const GlobalTransition& g = m.transitions[k];
    const Inst& in = m.insts[g.inst];
    const auto inputs = in.an.net.inputs(g.t);
    if (!inputs.empty()) m.consumers[in.place0 + inputs[0].node].push_back(k);
  }
  const Inst& mission = m.insts.front();
  for (PlaceId e : mission.cn->exits) {
    m.mission_exits.push_back(mission.place0 + e);
    if (q.to == BoundQuery::To::Exit && mission.an.net.place_name(e) == q.to_name) {
      m.to_exit = mission.place0 + e;
      to_seen = true;
    }
  }
  if (!event_seen) {
    switch (q.from) {
      case BoundQuery::From::Fault: return fmt::format("no net asks {}", q.from_name);
      case BoundQuery::From::Trip: return fmt::format("no guard named {} in the mission or its phases", q.from_name);
      case BoundQuery::From::Start: return fmt::format("no PHASE({}) in the mission or its phases", q.from_name);
    }
  }
  if (!to_seen) {
    if (q.to == BoundQuery::To::Exit) return fmt::format("the mission has no exit named {}", q.to_name);
    return q.to == BoundQuery::To::Surface ? std::string("no net calls exec surface")
                                           : fmt::format("no net calls {}", q.to_name);
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> build_model(const Program& program, const BoundQuery& query, const BoundOptions& options,
                                       Model& m) {
  const CompiledNet& mission = program.nets[*program.mission];
  Builder b(program, options, m);
  if (auto e = b.add(mission, {}, mission.name, 0)) return e;
  return finish_model(m, query);
}

}  // namespace strata::coral::timing_detail
