#pragma once
// One question about a P/T net (petri/question.h), answered with a witness,
// and a firing sequence replayed and checked (docs/verification.md,
// "Questions"): `--question Q`, `--replay SEQ` and `--replay-file FILE` of
// `strata verify --pnml FILE`, of `strata-pnml FILE` (cli/pnml_verify.h) and,
// on a mission's analysis net, of `strata verify MISSION`
// (cli/verify_question.h). Nothing here needs more of Strata than the nets:
// strata-pnml links it without the missions, PROLOG or the vehicle.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "petri/net.h"
#include "petri/question.h"

namespace strata::cli {

struct QuestionFlags {
  std::string question;     // --question: deadlock | EF φ | AG φ
  std::string replay;       // --replay: transition names
  std::string replay_file;  // --replay-file: the same in a file
  std::string net;          // --net: MISSION only, the net asked about
  bool no_reduction = false;
  std::string witness_out;            // --witness-out: MISSION only, the witness as vehicle answers
  std::string who = "strata verify";  // not a flag: what the messages start with
};

// Registers --question, --replay, --replay-file and --no-reduction; and,
// for a command that takes missions, --net.
void add_question_options(CLI::App& verify, QuestionFlags& flags, bool missions = true);

bool question_requested(const QuestionFlags& flags);

// Limits: max_states 0 = none; max_memory_mb 0 = none; time_limit_s 0 = none.
struct QuestionLimits {
  std::uint64_t max_states = 0;
  std::size_t max_memory_mb = 0;
  double time_limit_s = 0;
};

// The search's options for the flags and limits; the time limit counts
// from now.
petri::QuestionOptions question_options(const QuestionFlags& flags, const QuestionLimits& limits);

// Gets the witness found and returns an exit code (0: go on).
using WitnessSink = std::function<int(const std::vector<petri::TransitionId>&)>;

// The question or the replay of `flags` on one net, printed as text (its
// first line `header`) or one JSON document; labels (may be null) are the
// places' other names a predicate may use. on_witness (may be null) gets
// the witness found.
int ask_net(const petri::Net& net, const std::string& header, const std::vector<std::string>* labels,
            const QuestionFlags& flags, const std::string& format, petri::QuestionOptions qo,
            const WitnessSink& on_witness = nullptr);

// The question (or the replay) on the PNML net at `path`. Exit: 0 decided
// (or replayed to a marking that answers the question when one is given);
// 1 not decided (a limit, Ctrl-C), or a replay stopped at a transition not
// enabled or ending on a marking that does not answer the question; 64 a
// bad question or sequence; 65 a net Strata cannot read; 74 a file it
// cannot open.
int run_pnml_question(const std::string& path, const QuestionFlags& flags, const std::string& format,
                      const QuestionLimits& limits);

}  // namespace strata::cli
