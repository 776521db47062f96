#pragma once
// The markings a question's search (question.cpp) has visited. Not part of
// the API.
#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "petri/net.h"
#include "petri/packed_markings.h"

namespace strata::petri::question_detail {

// The visited markings in the full exploration's storage
// (packed_markings.h: bit fields, the markings in the slots of the hash
// table), and the current marking kept packed beside them (set() per place
// changed), so a lookup packs nothing. The fields start as wide as the
// initial tokens (no P-semiflows: most searches stop after a few markings);
// a count that does not fit widens its field and re-packs the table.
class MarkingStore {
 public:
  // A small table first: a widening re-packs all of it.
  static constexpr std::size_t kInitialSlots = 64;

  explicit MarkingStore(const Net& net) {
    set_.start(net, false, kInitialSlots);
    cur_.assign(set_.words(), 0);
    set_.pack(net.initial_marking(), cur_.data());
  }

  std::uint64_t size() const { return set_.size(); }
  std::size_t memory_bytes() const { return set_.table_bytes() + cur_.capacity() * sizeof(std::uint64_t); }

  // Place p of the current marking now holds v.
  void set(PlaceId p, Tokens v) {
    if (v > set_.field(p).mask) widen(p, v);
    packed::set(cur_.data(), set_.field(p), v);
  }

  bool contains_current() const { return set_.contains(cur_.data()); }

  // A change of one place's tokens (a transition's effect, place by place).
  struct Change {
    PlaceId place;
    std::int64_t by;
  };
  // Whether the successors of the current marking are stored, the current
  // marking left as it is: out[i] for the one changes_of(i) gives (a span
  // of Change; every count stays >= 0: the transition is enabled) is 1
  // (stored), 0 (not) or -1 (not known: a count would not fit its field,
  // and firing widens it). The successors are made from the packed words
  // and hashed, and their slots prefetched, before any lookup: the lookups'
  // cache misses overlap.
  template <class ChangesOf>
  void contains_after(std::size_t n, ChangesOf&& changes_of, std::vector<signed char>& out) {
    const std::size_t words = cur_.size();
    next_.resize(n * words);
    hashes_.resize(n);
    out.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      std::uint64_t* succ = &next_[i * words];
      std::copy(cur_.begin(), cur_.end(), succ);
      for (const Change& c : changes_of(i)) {
        const packed::Field& f = set_.field(c.place);
        if (c.by > 0 && packed::get(cur_.data(), f) + static_cast<std::uint64_t>(c.by) > f.mask) {
          out[i] = -1;
          break;
        }
        // No borrow or carry crosses the field's bounds: the count stays in it.
        succ[f.word] += static_cast<std::uint64_t>(c.by) << f.shift;
      }
      if (out[i] == -1) continue;
      hashes_[i] = set_.hash_of(succ);
      set_.prefetch(hashes_[i]);
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (out[i] == 0) out[i] = set_.contains(&next_[i * words], hashes_[i]) ? 1 : 0;
    }
  }
  // Adds the current marking when absent. Returns whether it was new.
  bool insert_current() { return set_.insert(cur_.data()); }

 private:
  void widen(PlaceId p, Tokens v) {
    const auto old = set_.widen_field(p, v);
    std::vector<std::uint64_t> m(set_.words());
    set_.repack(cur_.data(), old.first, m.data());
    cur_ = std::move(m);
  }

  packed::PackedMarkings set_;
  std::vector<std::uint64_t> cur_;
  // contains_after's scratch: the successors, their hashes.
  std::vector<std::uint64_t> next_, hashes_;
};

}  // namespace strata::petri::question_detail
