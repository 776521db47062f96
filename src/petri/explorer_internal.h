#pragma once
// The explorer's internals (explorer.h), shared by explorer.cpp (layout,
// table, breadth first) and explorer_liveness.cpp (the liveness pass). Not
// part of the API.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "petri/explorer.h"
#include "petri/net.h"
#include "petri/packed_markings.h"

namespace strata::petri::explorer_detail {

using packed::Field;
using packed::get;
using packed::kEmpty;
using packed::kInitialSlots;
using packed::kMaxBits;
using packed::kNoBound;
using packed::kNone;
using packed::mix;
using packed::Words;

// The breadth-first queue: copies of the markings not explored yet, in
// blocks of kBlockBytes taken at the tail and given back at the head, so it
// holds about what it queues (never an old and a new array at once, as a
// doubling ring did). One emptied block is kept for the next.
class MarkingQueue {
 public:
  static constexpr std::size_t kBlockBytes = std::size_t{1} << 16;

  explicit MarkingQueue(std::uint32_t words = 1)
      : words_(words), per_block_(std::max<std::size_t>(1, kBlockBytes / (words * sizeof(std::uint64_t)))) {}

  std::size_t size() const { return size_; }
  // The blocks held, the spare included.
  std::size_t bytes() const { return (blocks_.size() + (spare_ ? 1 : 0)) * block_bytes(); }
  // The bytes held once one more marking is pushed.
  std::size_t bytes_after_push() const { return bytes() + (needs_block() && !spare_ ? block_bytes() : 0); }

  // The k-th queued marking from the head (k < size()).
  const std::uint64_t* at(std::size_t k) const {
    const std::size_t i = head_ + k;
    return &blocks_[i / per_block_][(i % per_block_) * words_];
  }
  const std::uint64_t* front() const { return &blocks_.front()[head_ * words_]; }

  // Room for one more marking at the tail (words() words, to be written).
  std::uint64_t* push() {
    if (needs_block())
      blocks_.push_back(spare_ ? std::move(spare_) : std::make_unique_for_overwrite<std::uint64_t[]>(block_words()));
    const std::size_t i = head_ + size_++;
    return &blocks_.back()[(i - (blocks_.size() - 1) * per_block_) * words_];
  }
  void pop() {
    --size_;
    if (++head_ == per_block_) {
      spare_ = std::move(blocks_.front());
      blocks_.pop_front();
      head_ = 0;
    } else if (size_ == 0) {
      head_ = 0;
    }
  }

 private:
  std::size_t block_words() const { return per_block_ * words_; }
  std::size_t block_bytes() const { return block_words() * sizeof(std::uint64_t); }
  bool needs_block() const { return head_ + size_ == blocks_.size() * per_block_; }

  std::uint32_t words_;
  std::size_t per_block_;
  std::deque<std::unique_ptr<std::uint64_t[]>> blocks_;
  std::unique_ptr<std::uint64_t[]> spare_;
  std::size_t head_ = 0, size_ = 0;  // head_: index in the first block
};

// An input arc of a transition: the place's field and the weight.
struct InArc {
  Field field;
  std::uint64_t weight = 0;
  bool merged = false;  // several 1-bit places of weight 1: field.mask == weight
};

// A place a transition touches, with its weights in Pre and Post.
struct Touch {
  Field field;
  std::uint64_t pre = 0, post = 0;
  PlaceId place = 0;
};

// The 1-bit places of one word a transition touches, for the backward
// search (a predecessor m - Post(t) + Pre(t) exists when these hold): the
// bits Post(t) needs set in m, and the bits Pre(t) alone needs clear (a
// place in Pre(t) and not in Post(t) held a token before t fired and could
// not hold a second one).
struct BackTest {
  std::uint32_t word = 0;
  std::uint64_t set = 0, clear = 0;
};

// What a firing does to one word: m[word] - sub + add. Fields cannot borrow
// from each other (the transition is enabled) nor carry (no field
// overflows: checked, or the place is bounded by a P-semiflow).
struct Delta {
  std::uint32_t word = 0;
  std::uint64_t sub = 0, add = 0;
};

// Bits set (no popcnt instruction in the baseline x86-64 the build targets).
inline std::uint64_t popcount(std::uint64_t x) {
  x = x - ((x >> 1) & 0x5555555555555555ULL);
  x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
  x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0FULL;
  return (x * 0x0101010101010101ULL) >> 56;
}

// The packed markings (packed_markings.h) are the explorer's table.
class Explorer : private packed::PackedMarkings {
 public:
  Explorer(const Net& net, const ExploreOptions& options) : net_(net), opt_(options) {}

  ExploreResult run();

 private:
  // ---- layout ---------------------------------------------------------------
  // The fields laid out (layout_fields), then each transition's arcs, word
  // deltas and overflow checks in that layout.
  void layout();

  // The 1-bit places seen marked (seen_or_, in the current layout: call
  // before any change) into r_.place_bounds.
  void fold_bounds();

  std::vector<std::uint64_t> pack_initial() const;

  // Place p needs room for `value` tokens: widen its field and re-pack the
  // table and the queue. False when it cannot (more than 32 bits, or over
  // the memory limit): the exploration stops.
  bool widen(PlaceId p, std::uint64_t value);

  // Once kSemiflowsAfter states are found: the places a P-semiflow bounds
  // get fields as wide as their bounds, which never overflow (no checks), and
  // the table and the queue are re-packed. Computing the P-semiflows takes up
  // to tens of milliseconds on nets of a few hundred places, more than
  // exploring a small graph (IBM319-PT-none: 25 ms for 2,482 states). False
  // when the memory limit stops the exploration.
  static constexpr std::uint64_t kSemiflowsAfter = std::uint64_t{1} << 15;
  bool adopt_semiflow_bounds();

  // The fields changed (bits_, bounded_): lay them out and re-pack the table
  // and the queue from old_fields. False (stopped) when that would not fit
  // the memory limit; `what` says what needed it.
  bool relayout(const std::vector<Field>& old_fields, std::uint32_t old_words, const char* what);

  // ---- the set of markings: PackedMarkings' table ------------------------------
  std::size_t memory() const { return table_.bytes() + queue_.bytes(); }
  // The most memory() has been, the table's growth included.
  void note_peak(std::size_t bytes) { r_.peak_memory_bytes = std::max(r_.peak_memory_bytes, bytes); }
  bool fits(std::size_t bytes) const { return opt_.max_memory_bytes == 0 || bytes <= opt_.max_memory_bytes; }

  // Adds m if new (and queues it). False when a limit stops the exploration.
  template <unsigned W>
  bool insert(const std::uint64_t* m, std::uint64_t full_hash);

  bool full(std::size_t need);

  bool stop(std::string why);

  // True (now and then: the clock is read every 1024 calls) once the
  // deadline has passed, or once the progress callback, asked at least
  // every kProgressInterval whatever the count of states, says stop
  // (interrupted_): a Ctrl-C is prompt even where states come slowly (a
  // sanitizer build, a wide net) and in the liveness pass, which counts none.
  static constexpr auto kProgressInterval = std::chrono::milliseconds(100);
  bool past_deadline() {
    if ((++clock_calls_ & 1023) != 0) return false;
    if (opt_.deadline == std::chrono::steady_clock::time_point::max() && !opt_.progress) return false;
    const auto now = std::chrono::steady_clock::now();
    if (now > opt_.deadline) return true;
    if (opt_.progress && now - last_progress_ >= kProgressInterval) {
      last_progress_ = now;
      if (!opt_.progress({count_, explored_, r_.edges, memory()})) {
        interrupted_ = true;
        return true;
      }
    }
    return false;
  }

  // ---- breadth first: the queue holds copies of the markings not explored yet --
  void breadth_first();

  // The successors of one marking, hashed, their table slots prefetched.
  struct Batch {
    std::vector<std::uint64_t> succ, hashes;
    std::vector<TransitionId> fired;
    std::size_t n = 0;
    // A successor that does not fit: the place and its tokens (n is then
    // meaningless).
    PlaceId overflow_place = 0;
    std::uint64_t overflow_value = 0;
    bool overflow = false;
  };

  // The token counts of m (max_tokens_per_marking, place bounds).
  template <unsigned W>
  void count_tokens(const std::uint64_t* m);

  // Computes the successors of m into b (and, with statistics, the token
  // counts of m). False when one overflows a field.
  template <unsigned W>
  bool expand(const std::uint64_t* m, Batch& b);

  // True when a field widened (the layout changed: start again, with the
  // same queue head); false when done or stopped. Software-pipelined: the
  // successors of the next queued state are computed (and their slots
  // prefetched) before the lookups of this state's.
  template <unsigned W>
  bool breadth_first();

  // ---- liveness ----------------------------------------------------------------------
  bool enabled(const std::uint64_t* m, TransitionId t) const;

  // The successor of m by t (enabled, and it fits: the exploration saw it).
  void fire(const std::uint64_t* m, TransitionId t, std::uint64_t* out) const;

  // Live iff every transition is enabled somewhere in every bottom strongly
  // connected component of the reachability graph.
  void decide_liveness();

  // Backward search from the initial marking over the reversed edges: the
  // predecessors of m by t are m - Post(t) + Pre(t) when that is a stored
  // marking. True when it reaches every state.
  template <unsigned W>
  std::optional<bool> all_reach_initial();  // nullopt: the deadline passed

  // The predecessors of m, m - Post(t) + Pre(t) for each t where that is a
  // marking (stored or not), into b, hashed, their slots prefetched.
  template <unsigned W>
  void expand_back(const std::uint64_t* m, Batch& b);

  // Tarjan's strongly connected components over the table slots, successors
  // recomputed: true when every bottom component enables every transition.
  std::optional<bool> bottom_components_enable_all();  // nullopt: the deadline passed

  const Net& net_;
  ExploreOptions opt_;
  ExploreResult r_;
  // Layout.
  // Token counts (expand): per word, the bits at position k of every field
  // (total tokens = sum of popcounts << k); the OR of every marking seen
  // (the bounds of 1-bit places); the wider places whose bound may still
  // grow.
  struct Digit {
    std::uint32_t word = 0, k = 0;
    std::uint64_t mask = 0;
  };
  std::vector<Digit> digits_;
  std::vector<std::uint64_t> seen_or_;
  std::vector<PlaceId> track_;
  std::vector<InArc> in_;
  std::vector<Touch> touch_, checks_;  // checks_: the touches that may overflow
  std::vector<Delta> deltas_;
  std::vector<BackTest> back_;    // by transition: the 1-bit places touched
  std::vector<Touch> back_wide_;  // by transition: the other places touched
  std::vector<std::uint32_t> in_begin_, touch_begin_, check_begin_, delta_begin_, back_begin_, back_wide_begin_;
  MarkingQueue queue_;
  std::uint64_t explored_ = 0;
  std::uint64_t clock_calls_ = 0;
  std::chrono::steady_clock::time_point last_progress_ = std::chrono::steady_clock::now();
  bool interrupted_ = false;      // the progress callback said stop
  bool semiflow_bounds_ = false;  // adopt_semiflow_bounds() ran
  std::uint64_t next_progress_ = opt_.progress_every;
  // The successors (predecessors, going backwards) of this state and the
  // next one.
  Batch batches_[2];
};

}  // namespace strata::petri::explorer_detail
