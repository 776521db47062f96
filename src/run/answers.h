#pragma once
// A script of vehicle answers for a run (`strata run --answers FILE`,
// docs/verification.md "Witnesses as runs"): the file `strata verify
// --witness-out` writes (coral/witness.h has the format), read, bounded and
// checked against the mission before anything moves.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "coral/program.h"
#include "core/result.h"
#include "tactical/catalogue.h"

namespace strata::run {

// The largest answers file read, and the most answers it may hold.
inline constexpr std::size_t kMaxAnswersFileBytes = std::size_t{1} << 20;
inline constexpr std::size_t kMaxAnswers = 10'000;

struct ScriptedAnswer {
  std::size_t index = 0;   // in the file's "answers", from 0
  std::size_t step = 0;    // the witness step it answers (0: not given)
  std::string net;         // "" any net (PROLOG rules, or a hand-written script)
  std::string transition;  // "" any transition
  std::string action;      // "exec", "ask", "ood" or "phase"
  std::string primitive;   // the primitive, or the phase net
  bool value = false;      // exec, ask, ood: the answer the mission gets
  std::string exit;        // phase: the exit the phase must end at
  // "answers[3] (step 6, ASK depth_reached in check_depth)": where it is, for messages.
  std::string where() const;
};

struct AnswerScript {
  std::string path;  // as given
  std::string mission;
  std::string net;
  std::string from;
  std::vector<ScriptedAnswer> answers;
};

// The file's text parsed. Errors, InvalidInput, name the file and where:
// "FILE:LINE:COL: ..." for JSON that does not parse, "FILE: answers[3]:
// ..." for an entry that is wrong (an unknown key, a missing one, an answer
// that is not 0 or 1, too many answers).
core::Result<AnswerScript> parse_answers(std::string_view text, const std::string& path);

// The script checked against the mission: every primitive is the
// catalogue's and of the entry's kind (a suggestion when one is close); for
// CORAL, every net, transition and action is the program's and a phase's
// exit is one of its exits; PROLOG rules have no nets, so entries there name
// none. Errors: InvalidInput, "FILE: answers[3]: ...".
core::Result<void> check_answers(const AnswerScript& script, const tactical::Catalogue& catalogue,
                                 const coral::Program* program);

}  // namespace strata::run
