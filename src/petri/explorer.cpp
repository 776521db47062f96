#include "petri/explorer.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <new>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "petri/explorer_internal.h"

namespace strata::petri {
namespace explorer_detail {
ExploreResult Explorer::run() {
  const std::size_t places = net_.place_count();
  r_.place_bounds.assign(places, 0);
  r_.transition_fired.assign(net_.transition_count(), false);
  // The fields as wide as the initial tokens (widened on overflow) and an
  // empty table; the P-semiflows' bounds once the graph proves big enough
  // to pay for them (adopt_semiflow_bounds).
  start(net_, false);
  layout();
  queue_ = MarkingQueue(words_);
  std::vector<std::uint64_t> initial = pack_initial();
  bool out_of_memory = false;
  try {
    insert<0>(initial.data(), hash<0>(initial.data()));
    breadth_first();
  } catch (const std::bad_alloc&) {
    // The table may be half grown: counts so far, and no liveness pass.
    stop(fmt::format("stopped at {} states: out of memory", count_));
    out_of_memory = true;
  }
  r_.states = count_;
  r_.one_safe = r_.max_tokens_in_place <= 1;
  r_.quasi_live = std::all_of(r_.transition_fired.begin(), r_.transition_fired.end(), [](bool b) { return b; });
  r_.memory_bytes = memory();
  note_peak(r_.memory_bytes);
  r_.words_per_state = words_;
  if (!opt_.statistics) r_.live_why = "not computed (statistics off)";
  if (out_of_memory || !opt_.statistics) return std::move(r_);
  try {
    decide_liveness();
  } catch (const std::bad_alloc&) {
    r_.live.reset();
    r_.live_why = "the liveness pass ran out of memory";
  }
  return std::move(r_);
}

void Explorer::layout() {
  layout_fields();
  const std::size_t places = bits_.size();
  seen_or_.assign(words_, 0);
  digits_.clear();
  track_.clear();
  for (std::size_t p = 0; p < places; ++p) {
    const Field& f = fields_[p];
    for (std::uint32_t k = 0; k < bits_[p]; ++k) {
      std::size_t d = 0;
      while (d < digits_.size() && !(digits_[d].word == f.word && digits_[d].k == k)) ++d;
      if (d == digits_.size()) digits_.push_back({f.word, k, 0});
      digits_[d].mask |= 1ULL << (f.shift + k);
    }
    if (bits_[p] > 1 && r_.place_bounds[p] < bound_[p]) track_.push_back(static_cast<PlaceId>(p));
  }
  in_.clear();
  touch_.clear();
  checks_.clear();
  deltas_.clear();
  in_begin_.assign(1, 0);
  touch_begin_.assign(1, 0);
  back_.clear();
  back_wide_.clear();
  back_begin_.assign(1, 0);
  back_wide_begin_.assign(1, 0);
  check_begin_.assign(1, 0);
  delta_begin_.assign(1, 0);
  for (TransitionId t = 0; t < net_.transition_count(); ++t) {
    const std::size_t first_touch = touch_.size();
    auto touched = [&](PlaceId p) -> Touch& {
      for (std::size_t k = first_touch; k < touch_.size(); ++k) {
        if (touch_[k].place == p) return touch_[k];
      }
      touch_.push_back({fields_[p], 0, 0, p});
      return touch_.back();
    };
    // Inputs of weight 1 on 1-bit fields of one word merge into one test:
    // all the bits of a mask set (a field at shift 0, weight = mask).
    const std::size_t first_in = in_.size();
    for (const Arc& a : net_.inputs(t)) {
      const Field& f = fields_[a.node];
      touched(a.node).pre += a.weight;
      if (bits_[a.node] != 1 || a.weight != 1) {
        in_.push_back({f, a.weight, false});
        continue;
      }
      std::size_t k = first_in;
      while (k < in_.size() && !(in_[k].merged && in_[k].field.word == f.word)) ++k;
      if (k == in_.size()) in_.push_back({{f.word, 0, 0}, 0, true});
      in_[k].field.mask |= 1ULL << f.shift;
      in_[k].weight = in_[k].field.mask;
    }
    for (const Arc& a : net_.outputs(t)) touched(a.node).post += a.weight;
    const std::size_t first_delta = deltas_.size();
    for (std::size_t k = first_touch; k < touch_.size(); ++k) {
      const Touch& tc = touch_[k];
      if (!bounded_[tc.place] && tc.post > tc.pre) checks_.push_back(tc);
      if (bits_[tc.place] == 1 && tc.pre <= 1 && tc.post <= 1) {
        std::size_t b = back_begin_.back();
        while (b < back_.size() && back_[b].word != tc.field.word) ++b;
        if (b == back_.size()) back_.push_back({tc.field.word, 0, 0});
        (tc.post == 1 ? back_[b].set : back_[b].clear) |= 1ULL << tc.field.shift;
      } else {
        back_wide_.push_back(tc);
      }
      std::size_t d = first_delta;
      while (d < deltas_.size() && deltas_[d].word != tc.field.word) ++d;
      if (d == deltas_.size()) deltas_.push_back({tc.field.word, 0, 0});
      deltas_[d].sub += tc.pre << tc.field.shift;
      deltas_[d].add += tc.post << tc.field.shift;
    }
    in_begin_.push_back(static_cast<std::uint32_t>(in_.size()));
    touch_begin_.push_back(static_cast<std::uint32_t>(touch_.size()));
    back_begin_.push_back(static_cast<std::uint32_t>(back_.size()));
    back_wide_begin_.push_back(static_cast<std::uint32_t>(back_wide_.size()));
    check_begin_.push_back(static_cast<std::uint32_t>(checks_.size()));
    delta_begin_.push_back(static_cast<std::uint32_t>(deltas_.size()));
  }
}

void Explorer::fold_bounds() {
  if (seen_or_.empty()) return;
  for (PlaceId p = 0; p < fields_.size(); ++p) {
    if (bits_[p] == 1 && get(seen_or_.data(), fields_[p]) != 0)
      r_.place_bounds[p] = std::max<Tokens>(r_.place_bounds[p], 1);
  }
}

std::vector<std::uint64_t> Explorer::pack_initial() const {
  std::vector<std::uint64_t> m(words_, 0);
  for (PlaceId p = 0; p < net_.place_count(); ++p) set(m.data(), fields_[p], net_.initial_marking()[p]);
  return m;
}

bool Explorer::widen(PlaceId p, std::uint64_t value) {
  fold_bounds();  // seen_or_ is in the layout about to change
  const unsigned need = static_cast<unsigned>(std::bit_width(value));
  if (need > kMaxBits) {
    return stop(fmt::format("place '{}' would hold more than {} tokens", net_.place_name(p), kMaxTokens));
  }
  const std::vector<Field> old_fields = fields_;
  const std::uint32_t old_words = words_;
  bits_[p] = std::min(kMaxBits, std::max(need, bits_[p] * 2));
  return relayout(old_fields, old_words, "widening a field");
}

bool Explorer::adopt_semiflow_bounds() {
  semiflow_bounds_ = true;
  fold_bounds();
  const std::vector<Field> old_fields = fields_;
  const std::uint32_t old_words = words_;
  bound_ = packed::structural_bounds(net_);
  for (PlaceId p = 0; p < bits_.size(); ++p) {
    // Every marking stored so far fits the bound, whatever its field.
    if (bound_[p] != kNoBound && std::bit_width(bound_[p]) <= static_cast<int>(kMaxBits)) {
      bounded_[p] = true;
      bits_[p] = std::max(1u, static_cast<unsigned>(std::bit_width(bound_[p])));
    }
  }
  return relayout(old_fields, old_words, "the P-semiflows' field widths");
}

bool Explorer::relayout(const std::vector<Field>& old_fields, std::uint32_t old_words, const char* what) {
  layout();
  // The old and the new table at once, then the old and the new queue.
  const std::size_t table_after = Words::rounded(slots_ * words_ * sizeof(std::uint64_t));
  const std::size_t queue_after = (queue_.size() * words_ * sizeof(std::uint64_t) / MarkingQueue::kBlockBytes + 2) *
                                  (MarkingQueue::kBlockBytes + words_ * sizeof(std::uint64_t));
  const std::size_t bytes =
      std::max(table_.bytes() + table_after + queue_.bytes(), table_after + queue_.bytes() + queue_after);
  if (words_ != old_words && !fits(bytes)) {
    return stop(fmt::format("stopped at {} states: {} needs more than --max-memory", count_, what));
  }
  repack_table(old_fields, old_words);
  note_peak(last_growth_bytes_ + queue_.bytes());
  MarkingQueue old = std::move(queue_);
  queue_ = MarkingQueue(words_);
  for (std::size_t k = 0; k < old.size(); ++k) repack(old.at(k), old_fields, queue_.push());
  note_peak(memory() + old.bytes());
  return true;
}

template <unsigned W>
bool Explorer::insert(const std::uint64_t* m, std::uint64_t full_hash) {
  const std::uint32_t words = W ? W : words_;
  const std::size_t mask = slots_ - 1;
  std::size_t i = slot_of(full_hash);
  for (;; i = (i + 1) & mask) {
    const std::uint64_t* s = &table_[i * words];
    if (s[0] == kEmpty) break;
    if (equal<W>(s, m)) return true;
  }
  if (opt_.max_states && count_ >= opt_.max_states)
    return stop(fmt::format("stopped at {} states (the limit)", count_));
  if (count_ + 1 >= kNone) return stop("more than 4 294 967 294 states");
  if ((count_ + 1) * 4 > slots_ * 3) {
    // What the table holds while it grows (growth_bytes()).
    const std::size_t need = growth_bytes() + queue_.bytes();
    if (slots_ * 2 > std::size_t{1} << 31) return stop(fmt::format("stopped at {} states: the table's limit", count_));
    if (!fits(need)) return full(need);
    grow();
    note_peak(last_growth_bytes_ + queue_.bytes());
    i = slot_of(full_hash);
    while (table_[i * words] != kEmpty) i = (i + 1) & (slots_ - 1);
  }
  const std::size_t queue_bytes = queue_.bytes_after_push();
  if (queue_bytes != queue_.bytes()) {
    if (!fits(table_.bytes() + queue_bytes)) return full(table_.bytes() + queue_bytes);
    note_peak(table_.bytes() + queue_bytes);
  }
  std::memcpy(&table_[i * words], m, words * sizeof(std::uint64_t));
  std::memcpy(queue_.push(), m, words * sizeof(std::uint64_t));
  ++count_;
  return true;
}

bool Explorer::full(std::size_t need) {
  return stop(fmt::format("stopped at {} states: the next step needs {} MB, over --max-memory", count_, need >> 20));
}

bool Explorer::stop(std::string why) {
  if (r_.complete) {
    r_.complete = false;
    r_.stopped_why = std::move(why);
  }
  return false;
}

void Explorer::breadth_first() {
  for (;;) {
    const bool relayout = words_ == 1 ? breadth_first<1>() : words_ == 2 ? breadth_first<2>() : breadth_first<0>();
    if (!relayout) break;
  }
  fold_bounds();
  for (PlaceId p = 0; p < net_.place_count(); ++p) {
    r_.max_tokens_in_place = std::max(r_.max_tokens_in_place, r_.place_bounds[p]);
  }
}

template <unsigned W>
void Explorer::count_tokens(const std::uint64_t* m) {
  const std::uint32_t words = W ? W : words_;
  std::uint64_t total = 0;
  for (const Digit& d : digits_) total += popcount(m[d.word] & d.mask) << d.k;
  r_.max_tokens_per_marking = std::max(r_.max_tokens_per_marking, total);
  for (std::uint32_t k = 0; k < words; ++k) seen_or_[k] |= m[k];
  for (std::size_t i = 0; i < track_.size(); ++i) {
    const PlaceId p = track_[i];
    const std::uint64_t v = get(m, fields_[p]);
    if (v <= r_.place_bounds[p]) continue;
    r_.place_bounds[p] = static_cast<Tokens>(v);
    if (v >= bound_[p]) {  // no marking has more: stop looking
      track_[i--] = track_.back();
      track_.pop_back();
    }
  }
}

template <unsigned W>
bool Explorer::expand(const std::uint64_t* m, Batch& b) {
  const std::uint32_t words = W ? W : words_;
  const std::size_t transitions = net_.transition_count();
  if (opt_.statistics) count_tokens<W>(m);
  b.succ.resize(transitions * words + words);
  b.hashes.resize(transitions);
  b.fired.resize(transitions);
  b.overflow = false;
  std::size_t n = 0;
  for (TransitionId t = 0; t < transitions; ++t) {
    bool enabled = true;
    for (std::uint32_t i = in_begin_[t]; i < in_begin_[t + 1] && enabled; ++i) {
      enabled = get(m, in_[i].field) >= in_[i].weight;
    }
    if (!enabled) continue;
    for (std::uint32_t i = check_begin_[t]; i < check_begin_[t + 1]; ++i) {
      const Touch& c = checks_[i];
      const std::uint64_t v = get(m, c.field) - c.pre + c.post;
      if (v > c.field.mask) {
        b.overflow = true;
        b.overflow_place = c.place;
        b.overflow_value = v;
        return false;
      }
    }
    std::uint64_t* succ = &b.succ[n * words];
    for (std::uint32_t k = 0; k < words; ++k) succ[k] = m[k];
    for (std::uint32_t d = delta_begin_[t]; d < delta_begin_[t + 1]; ++d) {
      succ[deltas_[d].word] = succ[deltas_[d].word] - deltas_[d].sub + deltas_[d].add;
    }
    const std::uint64_t h = hash<W>(succ);
    b.hashes[n] = h;
    __builtin_prefetch(&table_[slot_of(h) * words]);
    b.fired[n] = t;
    ++n;
  }
  b.n = n;
  return true;
}

template <unsigned W>
bool Explorer::breadth_first() {
  const std::uint32_t words = W ? W : words_;
  Batch* now = &batches_[0];
  Batch* next = &batches_[1];
  if (queue_.size() == 0) return false;
  if (!expand<W>(queue_.front(), *now)) return widen(now->overflow_place, now->overflow_value);
  for (;;) {
    const bool ahead = queue_.size() >= 2;
    if (ahead) expand<W>(queue_.at(1), *next);
    for (std::size_t k = 0; k < now->n; ++k) {
      if (!insert<W>(&now->succ[k * words], now->hashes[k])) return false;
    }
    if (opt_.statistics) {
      for (std::size_t k = 0; k < now->n; ++k) r_.transition_fired[now->fired[k]] = true;
    }
    r_.edges += now->n;
    if (now->n == 0 && !r_.deadlock) {
      r_.deadlock = true;
      r_.first_deadlock = explored_;
    }
    queue_.pop();
    ++explored_;
    if (past_deadline()) {
      return stop(interrupted_ ? fmt::format("interrupted after {} states", count_)
                               : fmt::format("stopped at {} states: the time limit", count_));
    }
    if (opt_.progress && explored_ >= next_progress_) {
      next_progress_ += opt_.progress_every;
      if (!opt_.progress({count_, explored_, r_.edges, memory()})) {
        return stop(fmt::format("interrupted after {} states", count_));
      }
    }
    if (queue_.size() == 0) return false;
    if (!semiflow_bounds_ && count_ >= kSemiflowsAfter) return adopt_semiflow_bounds();
    if (ahead) {
      std::swap(now, next);
    } else {
      expand<W>(queue_.front(), *now);
    }
    if (now->overflow) return widen(now->overflow_place, now->overflow_value);
  }
}

}  // namespace explorer_detail

ExploreResult explore(const Net& net, const ExploreOptions& options) {
  return explorer_detail::Explorer(net, options).run();
}

}  // namespace strata::petri
