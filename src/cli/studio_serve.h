#pragma once
// `strata run MISSION --studio`: the run on the wall clock with the studio
// serving the mission's folder, its first stdout line the page's address.
// On a terminal it keeps serving after the run until Ctrl-C.
#include <cstdint>
#include <ostream>
#include <string>

#include "cli/mission_run.h"

namespace strata::cli {

RunReport serve_studio_run(RunOptions options, const std::string& host, std::uint16_t port, std::ostream& out,
                           std::ostream& err);

}  // namespace strata::cli
