#include "petri/question.h"

#include <algorithm>

#include <fmt/format.h>

#include "petri/question_store.h"
#include "petri/structural.h"
#include "petri/stubborn.h"

namespace strata::petri {

namespace {

using question_detail::MarkingStore;

// The largest number of markings (indexes are 32 bits).
constexpr std::uint64_t kMaxQuestionMarkings = 0xfffffff0ULL;

// Whether the stubborn sets pay, judged continuously. EF φ: computing them
// must cost at most kStepsPerPruned steps (stubborn.h's work) per
// transition they prune (firing a transition costs the search a few dozen
// steps, and a pruned one often saves the markings behind it too, hence
// the margin). Deadlock: one set may cost at most kStepsPerPruned steps per
// transition it could prune (its enabled transitions less one; past that
// it is the best found so far), and the sets are kept while they prune
// anything: fewer markings is the aim, and a marking pruned saves more
// than its set cost. Both counts are halved every kJudgeWindow sets (the
// judgement follows the net's phases); the first kJudgeAfter sets are not
// judged. While the sets do not pay, the search fires every enabled
// transition (a stubborn set too) and computes them again on one marking
// in kReductionRetry, which may turn them back on. Each marking may use any
// stubborn set: the argument in stubborn.h holds marking by marking.
constexpr std::uint64_t kStepsPerPruned = 256;
constexpr std::uint64_t kJudgeWindow = 64;
constexpr std::uint64_t kJudgeAfter = 16;
constexpr std::uint64_t kReductionRetry = 16;
constexpr std::uint64_t kReductionRetryMax = 4096;

class QuestionSearch {
 public:
  QuestionSearch(const Net& net, const Question& q, const QuestionOptions& o)
      : net_(net),
        q_(q),
        o_(o),
        store_(net),
        stubborn_(net),
        is_enabled_(net.transition_count(), 0),
        missing_(net.transition_count(), 0),
        enabled_at_(net.transition_count(), 0) {
    delta_begin_.push_back(0);
    // C(p, t) from t's own arcs (Net::incidence would search them per place).
    std::vector<std::int64_t> change(net.place_count(), 0);
    std::vector<TransitionId> input_of(net.place_count(), kNoTransition);
    for (TransitionId t = 0; t < net.transition_count(); ++t) {
      for (const Arc& a : net.outputs(t)) change[a.node] = a.weight;
      for (const Arc& a : net.inputs(t)) {
        input_of[a.node] = t;
        const std::int64_t c = change[a.node] - std::int64_t{a.weight};
        if (c != 0) deltas_.push_back({a.node, c});
      }
      for (const Arc& a : net.outputs(t)) {
        if (input_of[a.node] != t) deltas_.push_back({a.node, std::int64_t{a.weight}});
        change[a.node] = 0;
      }
      delta_begin_.push_back(static_cast<std::uint32_t>(deltas_.size()));
    }
  }

  void run(QuestionResult& r) {
    Marking m = net_.initial_marking();
    for (TransitionId t = 0; t < net_.transition_count(); ++t) {
      for (const Arc& a : net_.inputs(t)) missing_[t] += m[a.node] < a.weight ? 1 : 0;
      if (missing_[t] == 0) enable(t);
    }
    store_.insert_current();
    if (at_goal(m)) {
      found(r, m);
      return;
    }
    frames_.emplace_back(0, kNoTransition);
    candidates(m);
    r.edges += drop_stored(frames_.back().begin);
    std::uint64_t next_progress = o_.progress_every;
    auto last_progress = std::chrono::steady_clock::now();
    const std::uint64_t max_states =
        o_.max_states ? std::min(o_.max_states, kMaxQuestionMarkings) : kMaxQuestionMarkings;
    while (!frames_.empty()) {
      Frame& f = frames_.back();
      if (f.next == cand_.size()) {
        cand_.resize(f.begin);
        const TransitionId via = f.via;
        frames_.pop_back();
        if (!frames_.empty()) {
          apply(m, via, -1);
          update_missing(m, via, -1);
        }
        continue;
      }
      const TransitionId t = cand_[f.next++];
      if (!fits(m, t)) {
        stop(r, fmt::format("a place would hold more than {} tokens after firing '{}'", kMaxTokens,
                            net_.transition_name(t)));
        return;
      }
      apply(m, t, +1);
      ++r.edges;
      if (store_.size() >= max_states) {
        // Only a new marking would pass the limit.
        if (!store_.contains_current()) {
          stop(r, fmt::format("stopped at {} markings (the limit)", store_.size()));
          return;
        }
        apply(m, t, -1);
        continue;
      }
      if (!store_.insert_current()) {
        apply(m, t, -1);
        continue;
      }
      update_missing(m, t, +1);
      if (o_.max_memory_bytes && store_.memory_bytes() > o_.max_memory_bytes) {
        stop(r, fmt::format("stopped at {} markings: the store needs more than --max-memory", store_.size()));
        return;
      }
      // Every 4096 markings: the clock, for the deadline and for the
      // progress callback, asked at least every tenth of a second whatever
      // the count (Ctrl-C stays prompt where markings come slowly).
      bool progress_due = o_.progress && store_.size() >= next_progress;
      if (store_.size() % 4096 == 0) {
        const auto now = std::chrono::steady_clock::now();
        if (now >= o_.deadline) {
          stop(r, fmt::format("the time limit was reached after {} markings", store_.size()));
          return;
        }
        if (now - last_progress >= std::chrono::milliseconds(100)) progress_due = o_.progress != nullptr;
      }
      if (progress_due) {
        last_progress = std::chrono::steady_clock::now();
        if (store_.size() >= next_progress) next_progress += o_.progress_every;
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
      r.edges += drop_stored(frames_.back().begin);
    }
    r.answer = q_.kind == QuestionKind::Invariant ? Answer::Yes : Answer::No;
    finish(r);
  }

 private:
  static constexpr TransitionId kNoTransition = StubbornSets::kNoTransition;
  struct Frame {
    std::uint32_t begin = 0;  // its candidates: cand_[begin, end of cand_)
    TransitionId via = 0;     // fired to get here
    std::uint32_t next = 0;
    Frame(std::uint32_t b, TransitionId v) : begin(b), via(v), next(b) {}
  };
  using PlaceDelta = MarkingStore::Change;

  // Whether m is what the search looks for; sets terminal_.
  bool at_goal(const Marking& m) {
    terminal_ = false;
    for (PlaceId p : o_.terminal_places) terminal_ = terminal_ || m[p] > 0;
    if (q_.kind == QuestionKind::Deadlock) return !terminal_ && enabled_.empty();
    return q_.target.holds(m);
  }

  // Appends the transitions to try from m (enabled_ is m's enabled set;
  // none when terminal_).
  void candidates(const Marking& m) {
    ++visited_;
    if (terminal_) return;
    if (!reduce_ || enabled_.size() <= 1 || (!reducing_ && visited_ < next_retry_)) {
      cand_.insert(cand_.end(), enabled_.begin(), enabled_.end());
      return;
    }
    // A deadlock set's search stops at what it could save (all but one pruned).
    const std::uint64_t steps =
        q_.kind == QuestionKind::Deadlock
            ? stubborn_.for_deadlock(m, enabled_, is_enabled_, set_, kStepsPerPruned * (enabled_.size() - 1),
                                     frames_.back().via)
            : stubborn_.for_reaching(q_.target, m, is_enabled_, set_);
    cand_.insert(cand_.end(), set_.begin(), set_.end());
    judge(steps, enabled_.size() - set_.size());
  }

  // Takes out of cand_[begin, end) the transitions whose successor is
  // already stored (the store only grows: the search would step back from
  // it), looked up from the packed current marking without firing. Most
  // successors are old where the search prunes little (Dekker-PT-015: 60
  // transitions fired per new marking); firing each, looking it up and
  // taking it back cost the search twice the explorer's time. Returns how
  // many went (they count as fired).
  std::uint64_t drop_stored(std::uint32_t begin) {
    const TransitionId* ts = cand_.data() + begin;
    store_.contains_after(
        cand_.size() - begin,
        [&](std::size_t i) {
          return std::span<const PlaceDelta>(deltas_.data() + delta_begin_[ts[i]],
                                             deltas_.data() + delta_begin_[ts[i] + 1]);
        },
        stored_);
    std::size_t kept = begin;
    for (std::size_t k = begin; k < cand_.size(); ++k) {
      if (stored_[k - begin] != 1) cand_[kept++] = cand_[k];
    }
    const std::uint64_t dropped = cand_.size() - kept;
    cand_.resize(kept);
    return dropped;
  }

  // The continuous judgement (kStepsPerPruned).
  void judge(std::uint64_t steps, std::uint64_t pruned) {
    steps_ += steps;
    pruned_ += pruned;
    if (++sets_ % kJudgeWindow == 0) {
      steps_ /= 2;
      pruned_ /= 2;
    }
    if (sets_ < kJudgeAfter) return;
    const bool was = reducing_;
    reducing_ = q_.kind == QuestionKind::Deadlock ? pruned_ > 0 : steps_ <= kStepsPerPruned * pruned_;
    if (reducing_) {
      retry_gap_ = kReductionRetry;
    } else {
      if (!was) retry_gap_ = std::min(retry_gap_ * 2, kReductionRetryMax);  // a retry that did not pay
      next_retry_ = visited_ + retry_gap_;
    }
  }

  bool fits(const Marking& m, TransitionId t) const {
    for (std::uint32_t i = delta_begin_[t]; i < delta_begin_[t + 1]; ++i) {
      const PlaceDelta& d = deltas_[i];
      if (d.by > 0 && std::int64_t{m[d.place]} + d.by > std::int64_t{kMaxTokens}) return false;
    }
    return true;
  }
  // Fires t (sign +1; enabled, and fits) or takes it back (-1), in m and
  // in the store's current marking.
  void apply(Marking& m, TransitionId t, int sign) {
    for (std::uint32_t i = delta_begin_[t]; i < delta_begin_[t + 1]; ++i) {
      const PlaceDelta& d = deltas_[i];
      m[d.place] = static_cast<Tokens>(std::int64_t{m[d.place]} + sign * d.by);
      store_.set(d.place, m[d.place]);
    }
  }
  // The input arcs not satisfied, after t fired (+1) or was taken back
  // (-1): only the readers of the places t changes are looked at.
  void update_missing(const Marking& m, TransitionId t, int sign) {
    for (std::uint32_t i = delta_begin_[t]; i < delta_begin_[t + 1]; ++i) {
      const PlaceDelta& d = deltas_[i];
      const std::int64_t after = m[d.place];
      const std::int64_t before = after - sign * d.by;
      for (const Arc& r : net_.readers(d.place)) {
        const bool was = before >= r.weight, is = after >= r.weight;
        if (was && !is && missing_[r.node]++ == 0) disable(r.node);
        if (!was && is && --missing_[r.node] == 0) enable(r.node);
      }
    }
  }
  // enabled_ (in no order) and is_enabled_, kept as missing_ changes.
  void enable(TransitionId t) {
    is_enabled_[t] = 1;
    enabled_at_[t] = static_cast<std::uint32_t>(enabled_.size());
    enabled_.push_back(t);
  }
  void disable(TransitionId t) {
    is_enabled_[t] = 0;
    const TransitionId last = enabled_.back();
    enabled_[enabled_at_[t]] = last;
    enabled_at_[last] = enabled_at_[t];
    enabled_.pop_back();
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
  std::vector<std::uint32_t> missing_;     // by transition: input arcs not satisfied
  std::vector<std::uint32_t> enabled_at_;  // by enabled transition: its index in enabled_
  std::vector<std::uint32_t> delta_begin_;
  std::vector<PlaceDelta> deltas_;  // by transition: the places it changes
  std::vector<TransitionId> enabled_, set_, cand_;
  std::vector<Frame> frames_;
  std::vector<signed char> stored_;  // drop_stored's
  std::uint64_t visited_ = 0;
  std::uint64_t next_retry_ = 0, retry_gap_ = kReductionRetry;  // judge()
  std::uint64_t sets_ = 0, steps_ = 0, pruned_ = 0;             // judge()
  bool reduce_ = o_.reduction && o_.terminal_places.empty();
  bool reducing_ = true;
  bool terminal_ = false;  // the current marking has a token in a terminal place
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

core::Result<std::vector<TransitionId>, TextError> parse_sequence(std::string_view text, const Net& net) {
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
      return TextError{lines ? line : 0, start - line_start + 1, fmt::format("no transition '{}'", name)};
    }
    out.push_back(*t);
  }
  return out;
}

}  // namespace strata::petri
