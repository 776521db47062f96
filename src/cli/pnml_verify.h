#pragma once
// A P/T net in PNML, explored in full with the Model Checking Contest's
// global properties (deadlock, 1-safe, quasi-live, live), or asked one
// question (cli/net_question.h): `strata verify --pnml FILE` and
// `strata-pnml FILE`, the same analysis in a program of its own that loads
// only the nets (src/cli/pnml_main.cpp): no PROLOG, missions, studio or
// vehicle, so it starts in a fraction of strata's time and memory
// (docs/verification.md, "strata-pnml").
#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/net_question.h"

namespace strata::cli {

// The largest --max-memory, MB (1 PiB): shifted to bytes it still fits, and
// a negative number is refused rather than wrapped to a huge one.
inline constexpr std::size_t kMaxMemoryMb = std::size_t{1} << 30;

struct PnmlVerifyOptions {
  std::string path;
  std::string format = "text";    // text | json
  std::uint64_t max_states = 0;   // 0: none
  std::size_t max_memory_mb = 0;  // the process's, MB; 0: none
  double time_limit_s = 0;        // 0: none
  bool no_liveness = false;
  std::string who = "strata verify";  // what the messages start with
};

// The whole reachability graph and the properties, as text or one JSON
// document. Exit: 0 explored in full; 1 a limit or Ctrl-C stopped it (a
// partial report); 65 a net Strata cannot read; 74 a file it cannot open.
int run_verify_pnml(const PnmlVerifyOptions& options);

// The exit codes of both, for their --help.
extern const char* const kPnmlExitCodes;

// strata-pnml's command line. `strata manpages` writes its man page from
// the same app.
struct PnmlCommandLine {
  explicit PnmlCommandLine(const std::string& version);
  CLI::App app;
  PnmlVerifyOptions options;
  QuestionFlags question;
};

// After app.parse: the exploration, or the question or replay asked.
int run_pnml_command(PnmlCommandLine& line);

}  // namespace strata::cli
