#pragma once
// A place/transition net (P, T, A, w, x0) of the paper's §3.1, immutable once
// built. Arcs are kept per transition (Pre: inputs, Post: outputs) and per
// place (the transitions that read it), in flat arrays: a firing touches only
// the arcs of its transition and the readers of the places those arcs name.
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace strata::petri {

using PlaceId = std::uint32_t;
using TransitionId = std::uint32_t;
using Tokens = std::uint32_t;
using Marking = std::vector<Tokens>;  // indexed by PlaceId

inline constexpr Tokens kMaxTokens = std::numeric_limits<Tokens>::max();

// An arc seen from one end: `node` is the place (in a transition's Pre or
// Post list) or the transition (in a place's reader list); weight >= 1.
struct Arc {
  std::uint32_t node;
  std::uint32_t weight;
};

// Names of one kind of node, packed in one buffer: about 4 bytes of index per
// name plus its characters, instead of a std::string each.
class NameTable {
 public:
  NameTable() : begin_{0} {}
  void push_back(std::string_view name);
  std::size_t size() const { return begin_.size() - 1; }
  std::string_view at(std::uint32_t i) const {
    return std::string_view(chars_).substr(begin_[i], begin_[i + 1] - begin_[i]);
  }
  void reserve(std::size_t n) { begin_.reserve(n + 1); }
  std::size_t memory_bytes() const { return chars_.capacity() + begin_.capacity() * sizeof(std::uint32_t); }

 private:
  std::string chars_;
  std::vector<std::uint32_t> begin_;
};

class Net {
 public:
  std::size_t place_count() const { return place_names_.size(); }
  std::size_t transition_count() const { return transition_names_.size(); }
  // Number of arcs in A: Pre arcs plus Post arcs.
  std::size_t arc_count() const { return pre_.size() + post_.size(); }

  std::string_view place_name(PlaceId p) const { return place_names_.at(p); }
  std::string_view transition_name(TransitionId t) const { return transition_names_.at(t); }
  int priority(TransitionId t) const { return priorities_[t]; }
  const Marking& initial_marking() const { return initial_; }

  // I(t) with w(p, t): Pre.
  std::span<const Arc> inputs(TransitionId t) const {
    return {pre_.data() + pre_begin_[t], pre_.data() + pre_begin_[t + 1]};
  }
  // O(t) with w(t, p): Post.
  std::span<const Arc> outputs(TransitionId t) const {
    return {post_.data() + post_begin_[t], post_.data() + post_begin_[t + 1]};
  }
  // Transitions having p in their input set, with the weight w(p, t).
  std::span<const Arc> readers(PlaceId p) const {
    return {readers_.data() + readers_begin_[p], readers_.data() + readers_begin_[p + 1]};
  }
  // Transitions having p in their output set, with the weight w(t, p).
  std::span<const Arc> writers(PlaceId p) const {
    return {writers_.data() + writers_begin_[p], writers_.data() + writers_begin_[p + 1]};
  }

  std::uint32_t pre_weight(PlaceId p, TransitionId t) const;
  std::uint32_t post_weight(PlaceId p, TransitionId t) const;
  // C(p, t) = Post(p, t) - Pre(p, t). Never used for enabling: a self-loop
  // cancels out of C.
  std::int64_t incidence(PlaceId p, TransitionId t) const {
    return std::int64_t{post_weight(p, t)} - std::int64_t{pre_weight(p, t)};
  }

  std::optional<PlaceId> find_place(std::string_view name) const;
  std::optional<TransitionId> find_transition(std::string_view name) const;

  // Bytes held by this net, names and indexes included.
  std::size_t memory_bytes() const;

 private:
  friend class NetBuilder;
  NameTable place_names_;
  NameTable transition_names_;
  std::vector<int> priorities_;
  Marking initial_;
  std::vector<std::uint32_t> pre_begin_, post_begin_, readers_begin_, writers_begin_;
  std::vector<Arc> pre_, post_, readers_, writers_;
  // Ids sorted by name (then id), for find_*: copy-safe, 4 bytes a node.
  std::vector<PlaceId> places_by_name_;
  std::vector<TransitionId> transitions_by_name_;
};

// Collects places, transitions and arcs, then freezes them into a Net.
// Names need not be unique (find_* then returns the first); arcs given twice
// between the same pair are merged by adding their weights.
class NetBuilder {
 public:
  PlaceId add_place(std::string_view name, Tokens initial = 0);
  TransitionId add_transition(std::string_view name, int priority = 0);
  // Preconditions: ids were returned by this builder, weight >= 1.
  void add_input(TransitionId t, PlaceId p, std::uint32_t weight = 1);
  void add_output(TransitionId t, PlaceId p, std::uint32_t weight = 1);
  void reserve(std::size_t places, std::size_t transitions, std::size_t arcs);

  Net build() &&;

 private:
  struct PendingArc {
    TransitionId t;
    PlaceId p;
    std::uint32_t weight;
  };
  Net net_;
  std::vector<PendingArc> in_, out_;
};

// The paper's enabling rule: x(p) >= w(p, t) for every p in I(t).
bool is_enabled(const Net& net, const Marking& m, TransitionId t);

}  // namespace strata::petri
