#include "cli/verify_question.h"

#include <iostream>

#include <fmt/format.h>

#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/run_problems.h"
#include "cli/witness_out.h"
#include "coral/verify_question.h"
#include "run/coral_load.h"

namespace strata::cli {

int run_mission_question(const std::string& mission, const std::string& catalogue_option, const QuestionFlags& f,
                         const std::string& format, const QuestionLimits& limits) {
  auto catalogue = load_catalogue_option(catalogue_option);
  if (!catalogue) {
    std::cerr << "strata verify: " << catalogue.error().message << "\n";
    return exit_code_for_input(catalogue.error());
  }
  run::CoralLoad load = run::load_coral_file(mission, catalogue.value());
  if (int code = print_coral_load(std::cerr, load, "strata verify"); code != kExitOk) return code;
  petri::QuestionOptions qo = question_options(f, limits);
  auto an = coral::question_analysis_net(*load.program, f.net, qo);
  if (!an) {
    std::cerr << "strata verify: " << an.error().message << "\n";
    return kExitUsage;
  }
  qo.terminal_places = an.value().exits;
  const petri::Net& net = an.value().net;
  return ask_net(
      net,
      fmt::format("{} {} ({}): analysis net, {} places, {} transitions{}",
                  an.value().source->kind == coral::ast::Net::Kind::Mission ? "mission" : "phase",
                  an.value().source->name, an.value().source->source_file, net.place_count(), net.transition_count(),
                  qo.terminal_places.empty() ? "" : ", ends at its exits"),
      nullptr, f, format, qo,
      f.witness_out.empty() ? WitnessSink() : [&](const std::vector<petri::TransitionId>& path) {
        return write_path_witness(*load.program, an.value(), path, mission, f.question, f.witness_out);
      });
}

}  // namespace strata::cli
