#include "cli/witness_out.h"

#include <iostream>

#include <fmt/format.h>

#include "cli/exit_codes.h"
#include "coral/witness.h"
#include "core/file.h"

namespace strata::cli {
namespace {

int write_json(const nlohmann::ordered_json& j, const std::string& file, const std::string& what, std::size_t answers) {
  if (auto written = core::write_file_atomically(file, j.dump(2) + "\n"); !written) {
    std::cerr << fmt::format("strata verify: --witness-out: {}\n", written.error().message);
    return kExitIo;
  }
  std::cerr << fmt::format(
      "strata verify: {} written to {}: {} answer{} (`strata run MISSION --answers {}` "
      "follows it)\n",
      what, file, answers, answers == 1 ? "" : "s", file);
  return kExitOk;
}

}  // namespace

int write_report_witness(const coral::VerifyReport& report, const std::string& mission, const std::string& net,
                         const std::string& file) {
  if (!net.empty() && std::none_of(report.nets.begin(), report.nets.end(),
                                   [&](const coral::NetVerification& n) { return n.name == net; })) {
    std::string names;
    for (const auto& n : report.nets) names += (names.empty() ? "" : ", ") + n.name;
    std::cerr << fmt::format("strata verify: --net: no net '{}' was verified (the nets: {})\n", net, names);
    return kExitUsage;
  }
  // Blocking failures first: those are what stop a run.
  for (const bool blocking : {true, false}) {
    for (const auto& n : report.nets) {
      if (!net.empty() && n.name != net) continue;
      for (const auto& p : n.properties) {
        if (p.blocking != blocking || p.status != coral::Property::Status::Fails || !p.counterexample) continue;
        if (p.counterexample->timed) continue;  // a requirement's path crosses nets: no witness
        const auto& steps = p.counterexample->steps;
        const std::string from = fmt::format("{} counterexample", p.key);
        return write_json(coral::witness_answers_json(mission, n.name, from, steps), file,
                          fmt::format("the {} of {}", from, n.name), coral::answer_count(steps));
      }
    }
  }
  std::cerr << fmt::format(
      "strata verify: --witness-out: no property {}fails with a counterexample; nothing "
      "written\n",
      net.empty() ? "" : "of " + net + " ");
  return kExitAbort;
}

int write_path_witness(const coral::Program& program, const coral::AnalysisNet& an,
                       const std::vector<petri::TransitionId>& path, const std::string& mission,
                       const std::string& question, const std::string& file) {
  const auto steps = coral::trace_of(program, an, path);
  const std::string from = fmt::format("question '{}'", question);
  return write_json(coral::witness_answers_json(mission, an.source->name, from, steps), file, "the witness of " + from,
                    coral::answer_count(steps));
}

}  // namespace strata::cli
