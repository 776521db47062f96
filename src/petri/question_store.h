#pragma once
// The markings a question's search (question.cpp) has visited. Not part of
// the API.
#include <cstdint>
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
};

}  // namespace strata::petri::question_detail
