#pragma once
// `strata verify --pnml FILE --question Q` and `--replay SEQ` (and the
// same on a mission: `strata verify MISSION --question Q`): one question
// about a P/T net (petri/question.h), answered with a witness, and a firing
// sequence replayed and checked (docs/verification.md, "Questions"). The
// options are registered on the verify command; cmd_verify.cpp dispatches
// here when one of them is given.
#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

namespace strata::cli {

struct QuestionFlags {
  std::string question;     // --question: deadlock | EF φ | AG φ
  std::string replay;       // --replay: transition names
  std::string replay_file;  // --replay-file: the same in a file
  std::string net;          // --net: MISSION only, the net asked about
  bool no_reduction = false;
  std::string witness_out;  // --witness-out: MISSION only, the witness as vehicle answers
};

// Registers --question, --replay, --replay-file and --no-reduction.
void add_question_options(CLI::App& verify, QuestionFlags& flags);

bool question_requested(const QuestionFlags& flags);

// Limits: max_states 0 = none; max_memory_mb 0 = none; time_limit_s 0 = none.
struct QuestionLimits {
  std::uint64_t max_states = 0;
  std::size_t max_memory_mb = 0;
  double time_limit_s = 0;
};

// The question (or the replay) on the PNML net at `path`, printed as text or
// one JSON document. Exit: 0 decided (or replayed to a marking that answers
// the question when one is given); 1 not decided (a limit, Ctrl-C), or a
// replay stopped at a transition not enabled or ending on a marking that
// does not answer the question; 64 a bad question or sequence; 65 a net
// Strata cannot read; 74 a file it cannot open.
int run_pnml_question(const std::string& path, const QuestionFlags& flags, const std::string& format,
                      const QuestionLimits& limits);

// The same on the analysis net of one net of a CORAL mission
// (coral/verify_question.h), names as the mission writes them. Exit as
// above; 65 for a mission that does not compile; 64 for an unknown --net.
int run_mission_question(const std::string& mission, const std::string& catalogue, const QuestionFlags& flags,
                         const std::string& format, const QuestionLimits& limits);

}  // namespace strata::cli
