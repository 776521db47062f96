#include "petri/packed_markings.h"

#include <algorithm>
#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "petri/invariants.h"

namespace strata::petri::packed {

namespace {

// P-semiflows (for the place bounds) only on nets up to this many cells of
// the Farkas matrix, places * (places + transitions), and this many rows.
constexpr std::size_t kMaxSemiflowCells = std::size_t{1} << 21;
constexpr std::size_t kMaxSemiflowRows = 2000;

}  // namespace

std::vector<std::uint64_t> structural_bounds(const Net& net) {
  const std::size_t places = net.place_count();
  std::vector<std::uint64_t> bound(places, kNoBound);
  if (places == 0 || places * (places + net.transition_count()) > kMaxSemiflowCells) return bound;
  const Semiflows s = p_semiflows(net, kMaxSemiflowRows);
  for (const Semiflow& f : s.flows) {
    if (!is_p_invariant(net, f.weights)) continue;  // never expected; a wrong bound would corrupt markings
    for (const auto& [p, w] : f.weights) {
      if (w > 0) bound[p] = std::min(bound[p], f.constant / w);
    }
  }
  return bound;
}

Words::Words(std::size_t n) : n_(n), bytes_(rounded(n * 8)) {
  if (bytes_ >= kHuge) {
    p_ = static_cast<std::uint64_t*>(std::aligned_alloc(kHuge, bytes_));
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (p_) madvise(p_, bytes_, MADV_HUGEPAGE);
#endif
  } else {
    p_ = static_cast<std::uint64_t*>(std::malloc(std::max<std::size_t>(bytes_, 8)));
  }
  if (!p_) throw std::bad_alloc();
}

Words::~Words() { std::free(p_); }

void PackedMarkings::start(const Net& net, bool semiflow_bounds, std::size_t slots) {
  const std::size_t places = net.place_count();
  // Fields as wide as a P-semiflow bound when there is one (fixed: the
  // place cannot overflow); else as the initial tokens, widened on
  // overflow.
  bound_ = semiflow_bounds ? structural_bounds(net) : std::vector<std::uint64_t>(places, kNoBound);
  bits_.assign(places, 1);
  bounded_.assign(places, false);
  for (PlaceId p = 0; p < places; ++p) {
    const unsigned initial = static_cast<unsigned>(std::bit_width(net.initial_marking()[p]));
    if (bound_[p] != kNoBound && std::bit_width(bound_[p]) <= static_cast<int>(kMaxBits)) {
      bounded_[p] = true;
      bits_[p] = std::max(1u, static_cast<unsigned>(std::bit_width(bound_[p])));
    } else {
      bits_[p] = std::max(1u, initial);
    }
  }
  layout_fields();
  count_ = 0;
  new_table(slots);
}

void PackedMarkings::layout_fields() {
  const std::size_t places = bits_.size();
  fields_.resize(places);
  std::vector<unsigned> used;
  for (std::size_t p = 0; p < places; ++p) {
    std::size_t w = 0;
    while (w < used.size() && used[w] + bits_[p] > (w == 0 ? 63u : 64u)) ++w;
    if (w == used.size()) used.push_back(0);
    fields_[p] = {static_cast<std::uint32_t>(w), used[w], (1ULL << bits_[p]) - 1};
    used[w] += bits_[p];
  }
  words_ = std::max<std::uint32_t>(1, static_cast<std::uint32_t>(used.size()));
}

void PackedMarkings::pack(std::span<const Tokens> m, std::uint64_t* out) const {
  std::fill(out, out + words_, 0);
  for (PlaceId p = 0; p < m.size(); ++p) set(out, fields_[p], m[p]);
}

void PackedMarkings::new_table(std::size_t slots) {
  slots_ = slots;
  shift_ = 64 - static_cast<unsigned>(std::countr_zero(slots));
  table_ = Words(slots * words_);
  for (std::size_t i = 0; i < table_.size(); ++i) table_[i] = i % words_ == 0 ? kEmpty : 0;
}

void PackedMarkings::place(const std::uint64_t* m, std::uint64_t full_hash) {
  const std::size_t mask = slots_ - 1;
  std::size_t i = slot_of(full_hash);
  while (table_[i * words_] != kEmpty) i = (i + 1) & mask;
  std::memcpy(&table_[i * words_], m, words_ * sizeof(std::uint64_t));
}

void PackedMarkings::grow() {
  Words old = std::move(table_);
  new_table(slots_ * 2);
  for (std::size_t k = 0; k < old.size(); k += words_) {
    if (old[k] != kEmpty) place(&old[k], hash<0>(&old[k]));
  }
}

void PackedMarkings::repack(const std::uint64_t* from, const std::vector<Field>& old_fields, std::uint64_t* to) const {
  std::fill(to, to + words_, 0);
  for (std::size_t q = 0; q < fields_.size(); ++q) set(to, fields_[q], get(from, old_fields[q]));
}

void PackedMarkings::repack_table(const std::vector<Field>& old_fields, std::uint32_t old_words) {
  std::vector<std::uint64_t> m(words_);
  Words old_table = std::move(table_);
  new_table(slots_);
  for (std::size_t i = 0; i < slots_; ++i) {
    if (old_table[i * old_words] == kEmpty) continue;
    repack(&old_table[i * old_words], old_fields, m.data());
    place(m.data(), hash<0>(m.data()));
  }
}

std::pair<std::vector<Field>, std::uint32_t> PackedMarkings::widen_field(PlaceId p, std::uint64_t value) {
  std::pair<std::vector<Field>, std::uint32_t> old{fields_, words_};
  const unsigned need = static_cast<unsigned>(std::bit_width(value));
  bits_[p] = std::min(kMaxBits, std::max(need, bits_[p] * 2));
  layout_fields();
  repack_table(old.first, old.second);
  return old;
}

}  // namespace strata::petri::packed
