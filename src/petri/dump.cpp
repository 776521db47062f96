#include "petri/dump.h"

#include <fmt/format.h>

namespace strata::petri {
namespace {

std::string arcs(const Net& net, std::span<const Arc> list) {
  std::string s;
  for (const Arc& a : list) {
    if (!s.empty()) s += ", ";
    s += net.place_name(a.node);
    if (a.weight != 1) s += fmt::format("*{}", a.weight);
  }
  return s;
}

}  // namespace

std::string dump_net(const Net& net) {
  std::string out;
  for (PlaceId p = 0; p < net.place_count(); ++p) {
    out += fmt::format("place {} = {}\n", net.place_name(p), net.initial_marking()[p]);
  }
  for (TransitionId t = 0; t < net.transition_count(); ++t) {
    out += fmt::format("transition {}", net.transition_name(t));
    if (net.priority(t) != 0) out += fmt::format(" priority {}", net.priority(t));
    out += fmt::format(": in{{{}}} out{{{}}}\n", arcs(net, net.inputs(t)), arcs(net, net.outputs(t)));
  }
  return out;
}

std::string dump_marking(const Net& net, const Marking& m) {
  std::string out;
  for (PlaceId p = 0; p < net.place_count() && p < m.size(); ++p) {
    if (m[p] == 0) continue;
    if (!out.empty()) out += ' ';
    out += fmt::format("{}:{}", net.place_name(p), m[p]);
  }
  return out.empty() ? "(empty)" : out;
}

std::string dump_incidence(const Net& net) {
  std::string out;
  for (PlaceId p = 0; p < net.place_count(); ++p) {
    out += fmt::format("{}:", net.place_name(p));
    for (TransitionId t = 0; t < net.transition_count(); ++t) {
      out += fmt::format(" {}", net.incidence(p, t));
    }
    out += '\n';
  }
  return out;
}

}  // namespace strata::petri
