#pragma once
// A set of markings packed into 64-bit words, each place in a bit field:
// the full exploration's storage (explorer.h) and the question search's
// (question.h). Not part of the API.
//
// Layout: with start(net, true), a place covered by a P-semiflow y (y >= 0,
// y.C = 0) gets a field wide enough for its bound y.M0 / y(p) and never
// overflows; any other place starts as wide as its initial tokens, and a
// field that would overflow is widened (doubling: widen_field) and every
// stored marking re-packed (repack_table). First fit of the fields into
// words; word 0 keeps bit 63 free, so kEmpty marks a free slot.
//
// The set: an open-addressing hash table (linear probing, one cache miss
// per lookup; huge pages from 2 MB when the kernel allows) whose slots hold
// the packed markings themselves, 2^k slots, at most 3/4 full. It doubles
// without holding two full arrays (grow()).
//
// Threads: one per instance.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "petri/net.h"

namespace strata::petri::packed {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr unsigned kMaxBits = 32;  // Tokens are 32-bit
// Word 0 of a free table slot. No field uses bit 63 of word 0, so no packed
// marking has this word 0.
constexpr std::uint64_t kEmpty = ~0ULL;
constexpr std::uint64_t kNoBound = ~0ULL;
constexpr std::size_t kInitialSlots = 1024;

// Where one place's tokens live in a packed marking.
struct Field {
  std::uint32_t word = 0;
  std::uint32_t shift = 0;
  std::uint64_t mask = 0;  // the field's width, at the low bits
};

inline std::uint64_t get(const std::uint64_t* m, const Field& f) { return (m[f.word] >> f.shift) & f.mask; }
inline void set(std::uint64_t* m, const Field& f, std::uint64_t v) {
  m[f.word] = (m[f.word] & ~(f.mask << f.shift)) | (v << f.shift);
}

inline std::uint64_t mix(std::uint64_t x) {
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// By place: y.M0 / y(p) over the P-semiflows y covering p (every reachable
// marking has at most that many tokens in p), or kNoBound. Computed only on
// nets of moderate size (packed_markings.cpp).
std::vector<std::uint64_t> structural_bounds(const Net& net);

// An array of words for the hash table. From 2 MB on, it is mapped from the
// kernel directly in whole 2 MB pages (aligned) and the kernel asked for
// transparent huge pages: the lookups are random, and with 4 KB pages nearly
// every one also missed the TLB. Such an array is not initialised: its pages
// read 0 and take memory only once written, and discard() gives pages back.
// A smaller array comes from malloc, uninitialised. bytes() is what was
// allocated (rounded up).
class Words {
 public:
  static constexpr std::size_t kHuge = std::size_t{1} << 21;
  static constexpr std::size_t kPage = std::size_t{1} << 12;
  Words() = default;
  // The bytes an array of that many bytes takes.
  static std::size_t rounded(std::size_t bytes) { return bytes >= kHuge ? (bytes + kHuge - 1) / kHuge * kHuge : bytes; }
  explicit Words(std::size_t n);
  Words(Words&& o) noexcept
      : p_(std::exchange(o.p_, nullptr)), n_(std::exchange(o.n_, 0)), bytes_(std::exchange(o.bytes_, 0)) {}
  Words& operator=(Words&& o) noexcept {
    std::swap(p_, o.p_);
    std::swap(n_, o.n_);
    std::swap(bytes_, o.bytes_);
    return *this;
  }
  Words(const Words&) = delete;
  Words& operator=(const Words&) = delete;
  ~Words();

  std::size_t size() const { return n_; }
  std::size_t bytes() const { return bytes_; }
  // Mapped (from kHuge bytes on): discard() can give memory back.
  bool mapped() const { return bytes_ >= kHuge; }
  // Gives back the whole pages (kPage) within bytes [from, to) (mapped
  // arrays; otherwise nothing) and returns how many bytes that was. Those
  // words read 0 afterwards, and take memory again once written.
  std::size_t discard(std::size_t from, std::size_t to);
  std::uint64_t& operator[](std::size_t i) { return p_[i]; }
  const std::uint64_t& operator[](std::size_t i) const { return p_[i]; }

 private:
  std::uint64_t* p_ = nullptr;
  std::size_t n_ = 0, bytes_ = 0;
};

// The layout and the table. The explorer derives from it (its hot loops
// use the members directly); the question search uses the public part.
class PackedMarkings {
 public:
  PackedMarkings() = default;

  // Field widths for `net` (with `semiflow_bounds`, a P-semiflow's bound
  // where there is one; else the initial tokens, widened on overflow), their
  // layout, and an empty table of `slots` (a power of 2). The P-semiflows cost up to
  // tens of milliseconds on nets of a few hundred places: worth it for the
  // explorer, which visits every marking, not for a search that may stop
  // after a few.
  void start(const Net& net, bool semiflow_bounds, std::size_t slots = kInitialSlots);

  std::uint32_t words() const { return words_; }
  std::uint64_t size() const { return count_; }
  const Field& field(PlaceId p) const { return fields_[p]; }
  bool bounded(PlaceId p) const { return bounded_[p]; }
  std::size_t table_bytes() const { return table_.bytes(); }

  // m packed into out (words() words, zeroed first). Every count fits.
  void pack(std::span<const Tokens> m, std::uint64_t* out) const;

  // Inserts m (words() words) when absent, growing the table past 3/4
  // full (grow()). Returns whether it was new.
  bool insert(const std::uint64_t* m) {
    const std::uint64_t h = hash<0>(m);
    if (find<0>(m, h) != kNone) return false;
    if ((count_ + 1) * 4 > slots_ * 3) grow();
    place(m, h);
    ++count_;
    return true;
  }
  bool contains(const std::uint64_t* m) const { return find<0>(m, hash<0>(m)) != kNone; }
  // Batched lookups (the question's search): m's hash, a prefetch of the
  // slot a lookup with that hash starts at, and the lookup itself. Issuing
  // the prefetches of a batch before its lookups overlaps their cache misses.
  std::uint64_t hash_of(const std::uint64_t* m) const { return hash<0>(m); }
  void prefetch(std::uint64_t full_hash) const { __builtin_prefetch(&table_[slot_of(full_hash) * words_]); }
  bool contains(const std::uint64_t* m, std::uint64_t full_hash) const { return find<0>(m, full_hash) != kNone; }
  // The most bytes the table holds at once while it takes one more marking
  // (growing, if it has to: growth_bytes()).
  std::size_t bytes_after_insert() const { return (count_ + 1) * 4 > slots_ * 3 ? growth_bytes() : table_.bytes(); }
  // The most bytes the table holds at once while it doubles: the old and
  // the new array together while the old one is not mapped; else the new
  // one and what of the old one is not given back yet (grow()), within two
  // kHuge pages.
  std::size_t growth_bytes() const {
    const std::size_t bigger = Words::rounded(table_.size() * 16);
    return table_.mapped() ? bigger + 2 * Words::kHuge : table_.bytes() + bigger;
  }
  // The most bytes the table has held at once (its growth included).
  std::size_t peak_table_bytes() const { return std::max(peak_bytes_, table_.bytes()); }

  // Place p needs room for `value` tokens (at most 32 bits; the caller
  // checks): its field doubles (or more), the fields are laid out again
  // and every stored marking re-packed. The old fields and word count are
  // returned, to re-pack what the caller keeps (repack()).
  std::pair<std::vector<Field>, std::uint32_t> widen_field(PlaceId p, std::uint64_t value);
  // One marking from the old layout into the current one.
  void repack(const std::uint64_t* from, const std::vector<Field>& old_fields, std::uint64_t* to) const;

 protected:
  template <unsigned W>
  std::uint64_t hash(const std::uint64_t* m) const {
    const std::uint32_t words = W ? W : words_;
    std::uint64_t h = 0x9E3779B97F4A7C15ULL;
    for (std::uint32_t k = 0; k < words; ++k) h = mix(h ^ m[k]);
    return h;
  }

  template <unsigned W>
  bool equal(const std::uint64_t* a, const std::uint64_t* b) const {
    const std::uint32_t words = W ? W : words_;
    for (std::uint32_t k = 0; k < words; ++k) {
      if (a[k] != b[k]) return false;
    }
    return true;
  }

  std::size_t slot_of(std::uint64_t full_hash) const { return static_cast<std::size_t>(full_hash >> shift_); }
  const std::uint64_t* marking(std::size_t slot) const { return &table_[slot * words_]; }

  // The slot holding m, or kNone.
  template <unsigned W>
  std::uint32_t find(const std::uint64_t* m, std::uint64_t full_hash) const {
    const std::uint32_t words = W ? W : words_;
    const std::size_t mask = slots_ - 1;
    for (std::size_t i = slot_of(full_hash);; i = (i + 1) & mask) {
      const std::uint64_t* s = &table_[i * words];
      if (s[0] == kEmpty) return kNone;
      if (equal<W>(s, m)) return static_cast<std::uint32_t>(i);
    }
  }

  // First fit of the fields (bits_) into words.
  void layout_fields();
  void new_table(std::size_t slots);
  // Stores m, known to be absent, without any check (count_ unchanged).
  void place(const std::uint64_t* m, std::uint64_t full_hash);
  // Twice the slots, every marking placed again. A mapped table is not
  // held twice: the old slots are swept in order (a slot's marking lands at
  // about twice its index, slot_of() taking the hash's top bits), the new
  // array initialised just ahead of where they land and the old one given
  // back just behind the sweep.
  void grow();
  // Every stored marking from the old layout into the current one.
  void repack_table(const std::vector<Field>& old_fields, std::uint32_t old_words);

  std::vector<unsigned> bits_;
  std::vector<bool> bounded_;         // by place: the field has a P-semiflow bound
  std::vector<std::uint64_t> bound_;  // by place: that bound, or kNoBound
  std::vector<Field> fields_;
  std::uint32_t words_ = 1;
  // The table: slots_ packed markings, word 0 kEmpty when free.
  Words table_;
  std::size_t slots_ = 0;
  unsigned shift_ = 64;  // slot = hash >> shift_
  std::uint64_t count_ = 0;
  std::size_t peak_bytes_ = 0;         // peak_table_bytes()
  std::size_t last_growth_bytes_ = 0;  // the most the last grow() or repack_table() held at once
};

}  // namespace strata::petri::packed
