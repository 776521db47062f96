#pragma once
// `strata run MISSION --studio`: the run on the wall clock with the studio
// serving the mission's folder, its first stdout line the page's address.
// After the run it keeps serving: wait.seconds if given, else on a terminal
// until Ctrl-C (a stop signal ends any wait).
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

#include "cli/mission_run.h"

namespace strata::cli {

struct StudioRunWait {
  std::optional<double> seconds;  // --studio-wait
  bool terminal = false;          // stdin and stdout are a terminal
};

RunReport serve_studio_run(RunOptions options, const std::string& host, std::uint16_t port, const StudioRunWait& wait,
                           std::ostream& out, std::ostream& err);

}  // namespace strata::cli
