#include "cli/net_question.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <functional>
#include <iostream>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/exit_codes.h"
#include "core/file.h"
#include "petri/pnml.h"
#include "petri/question.h"

namespace strata::cli {

namespace {

constexpr std::size_t kMaxReplayFileBytes = std::size_t{16} << 20;

std::atomic<bool> g_question_interrupted{false};
extern "C" void on_question_interrupt(int) { g_question_interrupted = true; }

std::string marking_text(const petri::Net& net, const petri::Marking& m) {
  std::string out;
  for (petri::PlaceId p = 0; p < m.size(); ++p) {
    if (m[p] == 0) continue;
    out += fmt::format("{}{}:{}", out.empty() ? "" : " ", net.place_name(p), m[p]);
  }
  return out.empty() ? "(empty)" : out;
}

nlohmann::ordered_json marking_json(const petri::Net& net, const petri::Marking& m) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (petri::PlaceId p = 0; p < m.size(); ++p) {
    if (m[p] != 0) j[std::string(net.place_name(p))] = m[p];
  }
  return j;
}

std::string sequence_text(const petri::Net& net, const std::vector<petri::TransitionId>& seq) {
  std::string out;
  for (petri::TransitionId t : seq) out += fmt::format("{}{}", out.empty() ? "" : " ", net.transition_name(t));
  return out;
}

// "strata verify: --question 'EF p9 >= 1': column 4: no place 'p9'" and,
// for a text of one line, the text with a caret under the column.
void print_text_error(std::string_view who, const std::string& flag, const std::string& text,
                      const petri::TextError& error) {
  std::cerr << fmt::format("{}: {} '{}': {}\n", who, flag, text, error.text());
  if (error.column > 0 && error.line == 0 && text.find('\n') == std::string::npos) {
    std::cerr << "  " << text << "\n  " << std::string(error.column - 1, ' ') << "^\n";
  }
}

const char* answer_word(petri::Answer a) {
  switch (a) {
    case petri::Answer::Yes: return "yes";
    case petri::Answer::No: return "no";
    case petri::Answer::NotDecided: return "not decided";
  }
  return "?";
}

// What the answer means, for people.
std::string answer_meaning(const petri::Question& q, petri::Answer a) {
  using petri::Answer;
  using petri::QuestionKind;
  if (a == Answer::NotDecided) return "a limit stopped the search first";
  switch (q.kind) {
    case QuestionKind::Deadlock:
      return a == Answer::Yes ? "a reachable marking enables no transition"
                              : "every reachable marking enables a transition";
    case QuestionKind::Reachable:
      return a == Answer::Yes ? "a reachable marking satisfies the predicate" : "no reachable marking satisfies it";
    case QuestionKind::Invariant:
      return a == Answer::Yes ? "every reachable marking satisfies the predicate" : "a reachable marking violates it";
  }
  return "";
}

// Whether marking m answers the question as a witness would: a deadlock,
// or a marking the search looked for (φ for EF, !φ for AG).
bool is_witness(const petri::Question& q, bool deadlock, const petri::Marking& m) {
  return q.kind == petri::QuestionKind::Deadlock ? deadlock : q.target.holds(m);
}

int run_replay(const petri::Net& net, const std::string& header, const QuestionFlags& f,
               const std::optional<petri::Question>& q, const std::string& format,
               const std::vector<petri::PlaceId>& terminal) {
  std::string text = f.replay;
  std::string flag = "--replay";
  if (!f.replay_file.empty()) {
    auto read = core::read_regular_file(f.replay_file, kMaxReplayFileBytes);
    if (!read) {
      std::cerr << f.who << ": " << read.error().message << "\n";
      return exit_code_for_input(read.error());
    }
    text = std::move(read).value();
    flag = "--replay-file";
  }
  auto seq = petri::parse_sequence(text, net);
  if (!seq) {
    if (flag == "--replay") {
      print_text_error(f.who, flag, text, seq.error());
      return kExitUsage;
    }
    std::cerr << fmt::format("{}: {}: {}\n", f.who, f.replay_file, seq.error().text());
    return kExitInvalid;
  }
  petri::ReplayResult r = petri::replay(net, seq.value());
  // A marking at an exit ends the phase: nothing fires there, and it is no deadlock.
  for (petri::PlaceId p : terminal) r.deadlock = r.deadlock && r.marking[p] == 0;
  const bool answers = q && r.complete && is_witness(*q, r.deadlock, r.marking);
  if (format == "json") {
    nlohmann::ordered_json j;
    j["replayed"] = r.complete;
    j["fired"] = r.fired;
    j["length"] = seq.value().size();
    if (!r.complete) j["error"] = r.error;
    j["marking"] = marking_json(net, r.marking);
    j["deadlock"] = r.deadlock;
    if (q) {
      j["question"] = f.question;
      j["witness"] = answers;
    }
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << fmt::format("{}: replay of {} transition{}\n", header, seq.value().size(),
                             seq.value().size() == 1 ? "" : "s");
    if (r.complete) {
      std::cout << fmt::format("  fired      all {}\n", r.fired);
    } else {
      std::cout << fmt::format("  STOPPED    {}\n", r.error);
    }
    std::cout << fmt::format("  marking    {}\n", marking_text(net, r.marking));
    std::cout << fmt::format("  deadlock   {}\n", r.deadlock ? "yes: it enables no transition" : "no");
    if (q && q->kind != petri::QuestionKind::Deadlock) {
      std::cout << fmt::format("  predicate  {}\n", q->predicate.holds(r.marking) ? "holds" : "does not hold");
    }
    if (q) {
      std::cout << fmt::format("  witness    {} for '{}'\n", answers ? "yes" : "no", f.question);
    }
  }
  if (!r.complete) return kExitAbort;
  return !q || answers ? kExitOk : kExitAbort;
}

}  // namespace

petri::QuestionOptions question_options(const QuestionFlags& f, const QuestionLimits& limits) {
  petri::QuestionOptions qo;
  qo.reduction = !f.no_reduction;
  qo.max_states = limits.max_states;
  qo.max_memory_bytes = limits.max_memory_mb << 20;
  if (limits.time_limit_s > 0)  // from now: it covers a mission's phase questions too
    qo.deadline = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                         std::chrono::duration<double>(limits.time_limit_s));
  return qo;
}

void add_question_options(CLI::App& verify, QuestionFlags& f, bool missions) {
  auto* question =
      verify.add_option("--question", f.question,
                        "answer one question and stop at the first witness: 'deadlock', 'EF <predicate>' "
                        "(some reachable marking satisfies it) or 'AG <predicate>' (every one does); predicates "
                        "compare places and integers: 'p1 >= 2 && !(p3 == 0)' (docs/verification.md, Questions)");
  auto* replay = verify.add_option("--replay", f.replay,
                                   "fire these transitions (ids, separated by spaces) from the initial "
                                   "marking and print the marking reached; with --question, check it is a witness");
  auto* replay_file =
      verify.add_option("--replay-file", f.replay_file, "the same as --replay, the sequence read from a file");
  replay->excludes(replay_file);
  replay_file->excludes(replay);
  if (missions) {
    verify.add_option("--net", f.net,
                      "MISSION --question/--replay: the net to ask about (default: the mission net); places and "
                      "transitions are its analysis net's (docs/verification.md)");
  }
  auto* no_reduction = verify.add_flag("--no-reduction", f.no_reduction,
                                       "--question: search every interleaving (no stubborn sets); the same answer");
  no_reduction->needs(question);
}

bool question_requested(const QuestionFlags& f) {
  return !f.question.empty() || !f.replay.empty() || !f.replay_file.empty();
}

int ask_net(const petri::Net& net, const std::string& header, const std::vector<std::string>* labels,
            const QuestionFlags& f, const std::string& format, petri::QuestionOptions qo,
            const WitnessSink& on_witness) {
  std::optional<petri::Question> q;
  if (!f.question.empty()) {
    auto parsed = petri::parse_question(f.question, petri::net_place_resolver(net, labels));
    if (!parsed) {
      print_text_error(f.who, "--question", f.question, parsed.error());
      return kExitUsage;
    }
    q = std::move(parsed).value();
  }
  if (!f.replay.empty() || !f.replay_file.empty()) return run_replay(net, header, f, q, format, qo.terminal_places);

  const bool tty = isatty(STDERR_FILENO) == 1;
  const auto start = std::chrono::steady_clock::now();
  g_question_interrupted = false;
  auto previous = std::signal(SIGINT, on_question_interrupt);
  qo.progress = [&](const petri::ExploreProgress& p) {
    if (tty) std::cerr << fmt::format("\r  {} markings, {} MB   ", p.states, p.memory_bytes >> 20) << std::flush;
    return !g_question_interrupted.load();
  };
  const petri::QuestionResult r = petri::answer_question(net, *q, qo);
  const bool reduced = qo.reduction && qo.terminal_places.empty();
  std::signal(SIGINT, previous);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (tty && r.states >= qo.progress_every) std::cerr << "\r" << std::string(40, ' ') << "\r" << std::flush;

  const char* decided_by = !r.structural_reason.empty() ? "structure" : "search";
  if (format == "json") {
    nlohmann::ordered_json j;
    j["question"] = f.question;
    j["answer"] = answer_word(r.answer);
    j["decided_by"] = decided_by;
    if (!r.structural_reason.empty()) j["reason"] = r.structural_reason;
    if (r.answer == petri::Answer::NotDecided) j["stopped"] = r.stopped_why;
    if (r.has_witness) {
      nlohmann::ordered_json w = nlohmann::ordered_json::array();
      for (petri::TransitionId t : r.witness) w.push_back(std::string(net.transition_name(t)));
      j["witness"] = std::move(w);
      j["marking"] = marking_json(net, r.witness_marking);
    }
    j["markings_visited"] = r.states;
    j["transitions_fired"] = r.edges;
    j["reduction"] = reduced;
    j["seconds"] = seconds;
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << header << "\n";
    std::cout << fmt::format("  question   {}\n", f.question);
    std::cout << fmt::format("  answer     {}: {}\n", answer_word(r.answer), answer_meaning(*q, r.answer));
    if (!r.structural_reason.empty()) std::cout << fmt::format("  by         structure: {}\n", r.structural_reason);
    if (r.answer == petri::Answer::NotDecided) std::cout << fmt::format("  stopped    {}\n", r.stopped_why);
    if (r.has_witness) {
      std::cout << fmt::format("  witness    {} transition{}: {}\n", r.witness.size(), r.witness.size() == 1 ? "" : "s",
                               r.witness.empty() ? "(the initial marking)" : sequence_text(net, r.witness));
      std::cout << fmt::format("  marking    {}\n", marking_text(net, r.witness_marking));
    }
    if (r.structural_reason.empty()) {
      std::cout << fmt::format("  searched   {} markings, {} firings ({}) in {:.3f} s\n", r.states, r.edges,
                               reduced ? "stubborn sets" : "no reduction", seconds);
    }
  }
  if (on_witness) {
    if (!r.has_witness) {
      std::cerr << f.who << ": --witness-out: the answer has no witness; nothing written\n";
    } else if (const int code = on_witness(r.witness); code != kExitOk) {
      return code;
    }
  }
  return r.answer == petri::Answer::NotDecided ? kExitAbort : kExitOk;
}

int run_pnml_question(const std::string& path, const QuestionFlags& f, const std::string& format,
                      const QuestionLimits& limits) {
  if (!f.net.empty()) {
    std::cerr << f.who << ": --net names a net of a mission; a PNML file holds one net\n";
    return kExitUsage;
  }
  auto loaded = petri::read_pnml(path);
  if (!loaded) {
    std::cerr << f.who << ": " << loaded.error().message << "\n";
    return exit_code_for_input(loaded.error());
  }
  const petri::PnmlNet& pn = loaded.value();
  return ask_net(pn.net,
                 fmt::format("{} ({}): {} places, {} transitions, {} arcs", pn.name, path, pn.net.place_count(),
                             pn.net.transition_count(), pn.net.arc_count()),
                 &pn.place_labels, f, format, question_options(f, limits));
}

}  // namespace strata::cli
