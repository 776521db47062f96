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
// A growing table gives its old array back in steps of this many bytes.
constexpr std::size_t kGiveBack = std::size_t{1} << 18;

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
  if (mapped()) {
#if defined(__linux__)
    // Map a page more than needed and trim it to a kHuge boundary: huge
    // pages need the alignment. Not MAP_NORESERVE: a map the kernel would
    // not commit fails here (std::bad_alloc, a partial result), not later
    // when a page is written.
    const std::size_t span = bytes_ + kHuge;
    void* raw = mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) throw std::bad_alloc();
    const std::size_t head = (kHuge - reinterpret_cast<std::uintptr_t>(raw) % kHuge) % kHuge;
    char* start = static_cast<char*>(raw) + head;
    if (head > 0) munmap(raw, head);
    if (span > head + bytes_) munmap(start + bytes_, span - head - bytes_);
    p_ = static_cast<std::uint64_t*>(static_cast<void*>(start));
#if defined(MADV_HUGEPAGE)
    madvise(p_, bytes_, MADV_HUGEPAGE);
#endif
#else
    p_ = static_cast<std::uint64_t*>(std::aligned_alloc(kHuge, bytes_));
#endif
  } else {
    p_ = static_cast<std::uint64_t*>(std::malloc(std::max<std::size_t>(bytes_, 8)));
  }
  if (!p_) throw std::bad_alloc();
}

Words::~Words() {
  if (!p_) return;
#if defined(__linux__)
  if (mapped()) {
    munmap(p_, bytes_);
    return;
  }
#endif
  std::free(p_);
}

std::size_t Words::discard(std::size_t from, std::size_t to) {
  from = (from + kPage - 1) / kPage * kPage;
  to = std::min(to, bytes_) / kPage * kPage;
  if (!mapped() || from >= to) return 0;
#if defined(__linux__)
  if (madvise(reinterpret_cast<char*>(p_) + from, to - from, MADV_DONTNEED) != 0) return 0;
  return to - from;
#else
  return 0;
#endif
}

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
  peak_bytes_ = std::max(peak_bytes_, table_.bytes());
}

void PackedMarkings::place(const std::uint64_t* m, std::uint64_t full_hash) {
  const std::size_t mask = slots_ - 1;
  std::size_t i = slot_of(full_hash);
  while (table_[i * words_] != kEmpty) i = (i + 1) & mask;
  std::memcpy(&table_[i * words_], m, words_ * sizeof(std::uint64_t));
}

void PackedMarkings::grow() {
  Words old = std::move(table_);
  const std::size_t old_slots = slots_;
  const std::size_t old_bytes = old.bytes();
  if (Words::rounded(old.size() * 16) < Words::kHuge) {
    // Small: both arrays at once.
    new_table(slots_ * 2);
    last_growth_bytes_ = old_bytes + table_.bytes();
    peak_bytes_ = std::max(peak_bytes_, last_growth_bytes_);
    for (std::size_t k = 0; k < old.size(); k += words_) {
      if (old[k] != kEmpty) place(&old[k], hash<0>(&old[k]));
    }
    return;
  }
  table_ = Words(old.size() * 2);
  slots_ *= 2;
  shift_ -= 1;
  const std::size_t w = words_;
  const std::size_t slot_bytes = w * sizeof(std::uint64_t);
  // New slots [0, ready) are initialised (kEmpty or a marking); the rest of
  // the new array is untouched, and takes no memory yet.
  std::size_t ready = 0;
  std::size_t held = old_bytes;  // bytes written and not given back
  last_growth_bytes_ = held;
  auto prepare = [&](std::size_t slot) {
    // Up to the kHuge page holding `slot`'s last word, at least.
    const std::size_t end_byte =
        std::min(table_.bytes(), ((slot + 1) * slot_bytes + Words::kHuge - 1) / Words::kHuge * Words::kHuge);
    const std::size_t end = std::min(slots_, (end_byte + slot_bytes - 1) / slot_bytes);
    for (std::size_t i = ready; i < end; ++i) {
      table_[i * w] = kEmpty;
      for (std::size_t k = 1; k < w; ++k) table_[i * w + k] = 0;
    }
    held += (end - ready) * slot_bytes;
    ready = end;
    last_growth_bytes_ = std::max(last_growth_bytes_, held);
  };
  const std::size_t mask = slots_ - 1;
  auto put = [&](const std::uint64_t* m) {
    std::size_t i = slot_of(hash<0>(m));
    for (;; i = (i + 1) & mask) {
      if (i >= ready) prepare(i);
      if (table_[i * w] == kEmpty) break;
    }
    std::memcpy(&table_[i * w], m, slot_bytes);
  };
  // A run of full slots never crosses an empty one, so the markings after
  // the first empty slot e sit after their home slots, in the order of
  // their hashes: swept from e on, they land in the new array in ascending
  // order, and the old array can be given back behind the sweep. The slots
  // up to e (a run wrapped around the end, perhaps) come last.
  std::size_t e = 0;
  while (old[e * w] != kEmpty) ++e;
  std::size_t given_back = (e + 1) * slot_bytes;  // old bytes before this are kept to the end
  for (std::size_t j = e + 1; j < old_slots; ++j) {
    if (old[j * w] != kEmpty) put(&old[j * w]);
    const std::size_t done = (j + 1) * slot_bytes;
    if (done >= given_back + kGiveBack) {
      held -= old.discard(given_back, done);
      given_back = done / Words::kPage * Words::kPage;
    }
  }
  for (std::size_t j = 0; j < e; ++j) put(&old[j * w]);
  if (ready < slots_) prepare(slots_ - 1);
  peak_bytes_ = std::max(peak_bytes_, last_growth_bytes_);
}

void PackedMarkings::repack(const std::uint64_t* from, const std::vector<Field>& old_fields, std::uint64_t* to) const {
  std::fill(to, to + words_, 0);
  for (std::size_t q = 0; q < fields_.size(); ++q) set(to, fields_[q], get(from, old_fields[q]));
}

void PackedMarkings::repack_table(const std::vector<Field>& old_fields, std::uint32_t old_words) {
  std::vector<std::uint64_t> m(words_);
  Words old_table = std::move(table_);
  new_table(slots_);
  last_growth_bytes_ = old_table.bytes() + table_.bytes();
  peak_bytes_ = std::max(peak_bytes_, last_growth_bytes_);
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
