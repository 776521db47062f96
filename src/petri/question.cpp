#include "petri/question.h"

#include <cstring>
#include <limits>

#include <fmt/format.h>

#include "petri/stubborn.h"
#include "petri/structural.h"

namespace strata::petri {

namespace {

constexpr std::uint32_t kNoMarking = std::numeric_limits<std::uint32_t>::max();

std::uint64_t question_mix(std::uint64_t x) {
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

std::uint64_t hash_bytes(const std::uint8_t* p, std::size_t n) {
  std::uint64_t h = 0x9E3779B97F4A7C15ULL ^ n;
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, p + i, 8);
    h = question_mix(h ^ w);
  }
  if (i < n) {
    std::uint64_t w = 0;
    std::memcpy(&w, p + i, n - i);
    h = question_mix(h ^ w);
  }
  return h;
}

// The visited markings: packed one byte per place while every count is
// under 256, else four; an open-addressing table of indexes into them.
class MarkingStore {
 public:
  explicit MarkingStore(std::size_t places) : places_(places), scratch_(places * 4) { table_.assign(1024, kNoMarking); }

  std::uint64_t size() const { return count_; }
  std::size_t memory_bytes() const { return arena_.capacity() + table_.capacity() * 4; }

  bool contains(const Marking& m) {
    if (width_ == 1) {
      for (Tokens v : m) {
        if (v > 255) return false;
      }
    }
    const std::size_t bytes = places_ * width_;
    encode(m, scratch_.data());
    const std::size_t mask = table_.size() - 1;
    for (std::size_t i = hash_bytes(scratch_.data(), bytes) & mask;; i = (i + 1) & mask) {
      const std::uint32_t k = table_[i];
      if (k == kNoMarking) return false;
      if (std::memcmp(&arena_[k * bytes], scratch_.data(), bytes) == 0) return true;
    }
  }

  // Adds m when absent. Returns whether it was new.
  bool insert(const Marking& m) {
    if (width_ == 1) {
      for (Tokens v : m) {
        if (v > 255) {
          widen();
          break;
        }
      }
    }
    const std::size_t bytes = places_ * width_;
    encode(m, scratch_.data());
    if ((count_ + 1) * 2 > table_.size()) grow();
    const std::size_t mask = table_.size() - 1;
    for (std::size_t i = hash_bytes(scratch_.data(), bytes) & mask;; i = (i + 1) & mask) {
      const std::uint32_t k = table_[i];
      if (k == kNoMarking) {
        table_[i] = static_cast<std::uint32_t>(count_++);
        arena_.insert(arena_.end(), scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(bytes));
        return true;
      }
      if (std::memcmp(&arena_[k * bytes], scratch_.data(), bytes) == 0) return false;
    }
  }

 private:
  void encode(const Marking& m, std::uint8_t* out) const {
    if (width_ == 1) {
      for (std::size_t p = 0; p < places_; ++p) out[p] = static_cast<std::uint8_t>(m[p]);
    } else {
      std::memcpy(out, m.data(), places_ * 4);
    }
  }
  void widen() {
    std::vector<std::uint8_t> wide(arena_.size() * 4);
    for (std::size_t i = 0; i < arena_.size(); ++i) {
      const std::uint32_t v = arena_[i];
      std::memcpy(&wide[i * 4], &v, 4);
    }
    arena_ = std::move(wide);
    width_ = 4;
    rehash(table_.size());
  }
  void grow() { rehash(table_.size() * 2); }
  void rehash(std::size_t slots) {
    table_.assign(slots, kNoMarking);
    const std::size_t bytes = places_ * width_;
    const std::size_t mask = slots - 1;
    for (std::uint64_t k = 0; k < count_; ++k) {
      std::size_t i = hash_bytes(&arena_[k * bytes], bytes) & mask;
      while (table_[i] != kNoMarking) i = (i + 1) & mask;
      table_[i] = static_cast<std::uint32_t>(k);
    }
  }

  std::size_t places_;
  std::size_t width_ = 1;
  std::vector<std::uint8_t> arena_;
  std::vector<std::uint32_t> table_;
  std::vector<std::uint8_t> scratch_;
  std::uint64_t count_ = 0;
};

class QuestionSearch {
 public:
  QuestionSearch(const Net& net, const Question& q, const QuestionOptions& o)
      : net_(net), q_(q), o_(o), store_(net.place_count()), stubborn_(net), is_enabled_(net.transition_count(), 0) {}

  void run(QuestionResult& r) {
    Marking m = net_.initial_marking();
    store_.insert(m);
    if (at_goal(m)) {
      found(r, m);
      return;
    }
    frames_.emplace_back(0, kNoTransition);
    candidates(m);
    std::uint64_t next_progress = o_.progress_every;
    while (!frames_.empty()) {
      Frame& f = frames_.back();
      if (f.next == cand_.size()) {
        cand_.resize(f.begin);
        const TransitionId via = f.via;
        frames_.pop_back();
        if (!frames_.empty()) unfire(m, via);
        continue;
      }
      const TransitionId t = cand_[f.next++];
      if (!fire(m, t)) {
        stop(r, fmt::format("a place would hold more than {} tokens after firing '{}'", kMaxTokens,
                            net_.transition_name(t)));
        return;
      }
      ++r.edges;
      if (o_.max_states && store_.size() >= o_.max_states) {
        // Only a new marking would pass the limit.
        if (!store_.contains(m)) {
          stop(r, fmt::format("stopped at {} markings (the limit)", store_.size()));
          return;
        }
        unfire(m, t);
        continue;
      }
      if (!store_.insert(m)) {
        unfire(m, t);
        continue;
      }
      if (o_.max_memory_bytes && store_.memory_bytes() > o_.max_memory_bytes) {
        stop(r, fmt::format("stopped at {} markings: the store needs more than --max-memory", store_.size()));
        return;
      }
      if (o_.progress && store_.size() >= next_progress) {
        next_progress += o_.progress_every;
        if (!o_.progress({store_.size(), store_.size() - frames_.size(), r.edges, store_.memory_bytes()})) {
          stop(r, fmt::format("interrupted after {} markings", store_.size()));
          return;
        }
      }
      frames_.emplace_back(static_cast<std::uint32_t>(cand_.size()), t);
      if (at_goal(m)) {
        for (std::size_t k = 1; k < frames_.size(); ++k) r.witness.push_back(frames_[k].via);
        found(r, m);
        return;
      }
      candidates(m);
    }
    r.answer = q_.kind == QuestionKind::Invariant ? Answer::Yes : Answer::No;
    finish(r);
  }

 private:
  static constexpr TransitionId kNoTransition = std::numeric_limits<TransitionId>::max();
  struct Frame {
    std::uint32_t begin = 0;  // its candidates: cand_[begin, end of cand_)
    TransitionId via = 0;     // fired to get here
    std::uint32_t next = 0;
    Frame(std::uint32_t b, TransitionId v) : begin(b), via(v), next(b) {}
  };

  bool at_goal(const Marking& m) {
    enabled_.clear();
    for (TransitionId t = 0; t < net_.transition_count(); ++t) {
      bool on = true;
      for (const Arc& a : net_.inputs(t)) {
        if (m[a.node] < a.weight) {
          on = false;
          break;
        }
      }
      if (on) enabled_.push_back(t);
    }
    if (q_.kind == QuestionKind::Deadlock) return enabled_.empty();
    return q_.target.holds(m);
  }

  // Appends the transitions to try from m (enabled_ is m's enabled set).
  void candidates(const Marking& m) {
    if (!o_.reduction) {
      cand_.insert(cand_.end(), enabled_.begin(), enabled_.end());
      return;
    }
    for (TransitionId t : enabled_) is_enabled_[t] = 1;
    if (q_.kind == QuestionKind::Deadlock) {
      stubborn_.for_deadlock(m, enabled_, is_enabled_, set_);
    } else {
      stubborn_.for_reaching(q_.target, m, is_enabled_, set_);
    }
    for (TransitionId t : enabled_) is_enabled_[t] = 0;
    cand_.insert(cand_.end(), set_.begin(), set_.end());
  }

  // False (m unchanged) when a place would overflow.
  bool fire(Marking& m, TransitionId t) const {
    for (const Arc& a : net_.outputs(t)) {
      const std::uint64_t v = std::uint64_t{m[a.node]} - net_.pre_weight(a.node, t) + a.weight;
      if (v > kMaxTokens) return false;
    }
    for (const Arc& a : net_.inputs(t)) m[a.node] -= a.weight;
    for (const Arc& a : net_.outputs(t)) m[a.node] += a.weight;
    return true;
  }
  void unfire(Marking& m, TransitionId t) const {
    for (const Arc& a : net_.outputs(t)) m[a.node] -= a.weight;
    for (const Arc& a : net_.inputs(t)) m[a.node] += a.weight;
  }

  void found(QuestionResult& r, const Marking& m) {
    r.has_witness = true;
    r.witness_marking = m;
    r.answer = q_.kind == QuestionKind::Invariant ? Answer::No : Answer::Yes;
    finish(r);
  }
  void stop(QuestionResult& r, std::string why) {
    r.answer = Answer::NotDecided;
    r.stopped_why = std::move(why);
    finish(r);
  }
  void finish(QuestionResult& r) const {
    r.states = store_.size();
    r.memory_bytes = store_.memory_bytes();
  }

  const Net& net_;
  const Question& q_;
  const QuestionOptions& o_;
  MarkingStore store_;
  StubbornSets stubborn_;
  std::vector<char> is_enabled_;
  std::vector<TransitionId> enabled_, set_, cand_;
  std::vector<Frame> frames_;
};

}  // namespace

QuestionResult answer_question(const Net& net, const Question& question, const QuestionOptions& options) {
  QuestionResult r;
  if (options.structural) {
    std::optional<StructuralAnswer> s;
    if (question.kind == QuestionKind::Deadlock) {
      s = deadlock_by_structure(net);
    } else {
      s = reachable_by_structure(net, question.target, structural_ranges(net));
    }
    if (s) {
      // s->yes: the search target is reachable; only "no" is proved here.
      const bool target_reachable = s->yes;
      r.answer = (question.kind == QuestionKind::Invariant) != target_reachable ? Answer::Yes : Answer::No;
      r.structural_reason = std::move(s->reason);
      return r;
    }
  }
  QuestionSearch(net, question, options).run(r);
  return r;
}

ReplayResult replay(const Net& net, std::span<const TransitionId> sequence) {
  ReplayResult r;
  r.marking = net.initial_marking();
  for (TransitionId t : sequence) {
    if (!is_enabled(net, r.marking, t)) {
      std::string missing;
      for (const Arc& a : net.inputs(t)) {
        if (r.marking[a.node] < a.weight) {
          missing += fmt::format("{}{} has {} of {}", missing.empty() ? "" : ", ", net.place_name(a.node),
                                 r.marking[a.node], a.weight);
        }
      }
      r.error = fmt::format("step {}: '{}' is not enabled ({})", r.fired + 1, net.transition_name(t), missing);
      break;
    }
    for (const Arc& a : net.outputs(t)) {
      const std::uint64_t v = std::uint64_t{r.marking[a.node]} - net.pre_weight(a.node, t) + a.weight;
      if (v > kMaxTokens) {
        r.error = fmt::format("step {}: firing '{}' puts more than {} tokens in '{}'", r.fired + 1,
                              net.transition_name(t), kMaxTokens, net.place_name(a.node));
        break;
      }
    }
    if (!r.error.empty()) break;
    for (const Arc& a : net.inputs(t)) r.marking[a.node] -= a.weight;
    for (const Arc& a : net.outputs(t)) r.marking[a.node] += a.weight;
    ++r.fired;
  }
  r.complete = r.error.empty();
  r.deadlock = true;
  for (TransitionId t = 0; t < net.transition_count() && r.deadlock; ++t) r.deadlock = !is_enabled(net, r.marking, t);
  return r;
}

core::Result<std::vector<TransitionId>> parse_sequence(std::string_view text, const Net& net) {
  std::vector<TransitionId> out;
  const bool lines = text.find('\n') != std::string_view::npos;
  std::size_t line = 1, line_start = 0;
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      line_start = ++i;
      continue;
    }
    if (c == ' ' || c == '\t' || c == '\r' || c == ',') {
      ++i;
      continue;
    }
    if (c == '#') {
      while (i < text.size() && text[i] != '\n') ++i;
      continue;
    }
    const std::size_t start = i;
    while (i < text.size() && std::string_view(" \t\r\n,#").find(text[i]) == std::string_view::npos) ++i;
    const std::string_view name = text.substr(start, i - start);
    auto t = net.find_transition(name);
    if (!t) {
      const std::size_t column = start - line_start + 1;
      return core::Error{core::ErrorCode::InvalidInput,
                         lines ? fmt::format("line {}, column {}: no transition '{}'", line, column, name)
                               : fmt::format("column {}: no transition '{}'", column, name)};
    }
    out.push_back(*t);
  }
  return out;
}

}  // namespace strata::petri
