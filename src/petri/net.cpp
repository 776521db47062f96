#include "petri/net.h"

#include <algorithm>
#include <cassert>

namespace strata::petri {
namespace {

struct Keyed {
  std::uint32_t key;
  std::uint32_t node;
  std::uint32_t weight;
};

// Groups arcs by key into CSR form: begin has key_count + 1 offsets. Arcs
// with the same key and node are merged (weights added, saturating).
void to_csr(std::vector<Keyed> arcs, std::size_t key_count, std::vector<std::uint32_t>& begin, std::vector<Arc>& out) {
  std::stable_sort(arcs.begin(), arcs.end(),
                   [](const Keyed& a, const Keyed& b) { return a.key != b.key ? a.key < b.key : a.node < b.node; });
  begin.assign(key_count + 1, 0);
  out.clear();
  out.reserve(arcs.size());
  std::size_t i = 0;
  for (std::uint32_t k = 0; k < key_count; ++k) {
    begin[k] = static_cast<std::uint32_t>(out.size());
    while (i < arcs.size() && arcs[i].key == k) {
      if (!out.empty() && out.size() > begin[k] && out.back().node == arcs[i].node) {
        std::uint64_t sum = std::uint64_t{out.back().weight} + arcs[i].weight;
        out.back().weight = static_cast<std::uint32_t>(std::min<std::uint64_t>(sum, kMaxTokens));
      } else {
        out.push_back({arcs[i].node, arcs[i].weight});
      }
      ++i;
    }
  }
  begin[key_count] = static_cast<std::uint32_t>(out.size());
  out.shrink_to_fit();
}

std::uint32_t weight_in(std::span<const Arc> arcs, std::uint32_t node) {
  // Arcs are sorted by node within a transition.
  auto it = std::lower_bound(arcs.begin(), arcs.end(), node, [](const Arc& a, std::uint32_t n) { return a.node < n; });
  return it != arcs.end() && it->node == node ? it->weight : 0;
}

std::vector<std::uint32_t> sorted_by_name(const NameTable& names) {
  std::vector<std::uint32_t> ids(names.size());
  for (std::uint32_t i = 0; i < ids.size(); ++i) ids[i] = i;
  std::stable_sort(ids.begin(), ids.end(), [&](std::uint32_t a, std::uint32_t b) { return names.at(a) < names.at(b); });
  return ids;
}

std::optional<std::uint32_t> find_by_name(const NameTable& names, const std::vector<std::uint32_t>& sorted,
                                          std::string_view name) {
  auto it = std::lower_bound(sorted.begin(), sorted.end(), name,
                             [&](std::uint32_t id, std::string_view n) { return names.at(id) < n; });
  if (it == sorted.end() || names.at(*it) != name) return std::nullopt;
  return *it;
}

}  // namespace

std::uint32_t Net::pre_weight(PlaceId p, TransitionId t) const { return weight_in(inputs(t), p); }
std::uint32_t Net::post_weight(PlaceId p, TransitionId t) const { return weight_in(outputs(t), p); }

std::optional<PlaceId> Net::find_place(std::string_view name) const {
  return find_by_name(place_names_, places_by_name_, name);
}

std::optional<TransitionId> Net::find_transition(std::string_view name) const {
  return find_by_name(transition_names_, transitions_by_name_, name);
}

void NameTable::push_back(std::string_view name) {
  chars_.append(name);
  begin_.push_back(static_cast<std::uint32_t>(chars_.size()));
}

std::size_t Net::memory_bytes() const {
  auto vec = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return sizeof(*this) + place_names_.memory_bytes() + transition_names_.memory_bytes() + vec(priorities_) +
         vec(initial_) + vec(pre_begin_) + vec(post_begin_) + vec(readers_begin_) + vec(writers_begin_) + vec(pre_) +
         vec(post_) + vec(readers_) + vec(writers_) + vec(places_by_name_) + vec(transitions_by_name_);
}

PlaceId NetBuilder::add_place(std::string_view name, Tokens initial) {
  net_.place_names_.push_back(name);
  net_.initial_.push_back(initial);
  return static_cast<PlaceId>(net_.place_names_.size() - 1);
}

TransitionId NetBuilder::add_transition(std::string_view name, int priority) {
  net_.transition_names_.push_back(name);
  net_.priorities_.push_back(priority);
  return static_cast<TransitionId>(net_.transition_names_.size() - 1);
}

void NetBuilder::add_input(TransitionId t, PlaceId p, std::uint32_t weight) {
  assert(t < net_.transition_names_.size() && p < net_.place_names_.size() && weight >= 1);
  in_.push_back({t, p, weight});
}

void NetBuilder::add_output(TransitionId t, PlaceId p, std::uint32_t weight) {
  assert(t < net_.transition_names_.size() && p < net_.place_names_.size() && weight >= 1);
  out_.push_back({t, p, weight});
}

void NetBuilder::reserve(std::size_t places, std::size_t transitions, std::size_t arcs) {
  net_.place_names_.reserve(places);
  net_.initial_.reserve(places);
  net_.transition_names_.reserve(transitions);
  net_.priorities_.reserve(transitions);
  in_.reserve(arcs);
  out_.reserve(arcs);
}

Net NetBuilder::build() && {
  Net net = std::move(net_);
  const std::size_t np = net.place_names_.size();
  const std::size_t nt = net.transition_names_.size();
  std::vector<Keyed> by_t, by_p;
  by_t.reserve(in_.size());
  by_p.reserve(in_.size());
  for (const auto& a : in_) {
    by_t.push_back({a.t, a.p, a.weight});
    by_p.push_back({a.p, a.t, a.weight});
  }
  in_.clear();
  in_.shrink_to_fit();
  to_csr(std::move(by_t), nt, net.pre_begin_, net.pre_);
  to_csr(std::move(by_p), np, net.readers_begin_, net.readers_);
  by_t.clear();
  by_p.clear();
  for (const auto& a : out_) {
    by_t.push_back({a.t, a.p, a.weight});
    by_p.push_back({a.p, a.t, a.weight});
  }
  out_.clear();
  out_.shrink_to_fit();
  to_csr(std::move(by_t), nt, net.post_begin_, net.post_);
  to_csr(std::move(by_p), np, net.writers_begin_, net.writers_);

  net.places_by_name_ = sorted_by_name(net.place_names_);
  net.transitions_by_name_ = sorted_by_name(net.transition_names_);
  return net;
}

bool is_enabled(const Net& net, const Marking& m, TransitionId t) {
  for (const Arc& a : net.inputs(t)) {
    if (m[a.node] < a.weight) return false;
  }
  return true;
}

}  // namespace strata::petri
