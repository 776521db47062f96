// `strata export --pnml|--dot MISSION`: a mission's nets for other tools.
#include <filesystem>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "cli/commands.h"
#include "cli/run_problems.h"
#include "run/coral_load.h"
#include "cli/exit_codes.h"
#include "cli/mission_files.h"
#include "coral/export.h"
#include "coral/verifier.h"
#include "core/file.h"
#include "core/mission_language.h"

namespace strata::cli {
namespace {

namespace fs = std::filesystem;

struct ExportOptions {
  std::string mission;
  bool pnml = false;
  bool dot = false;
  std::string net;
  std::string output;
  std::string catalogue;
};

bool write_file(const fs::path& path, const std::string& text) {
  if (auto written = core::write_file_atomically(path, text); !written) {
    std::cerr << fmt::format("strata export: {}\n", written.error().message);
    return false;
  }
  std::cerr << fmt::format("wrote {}\n", path.string());
  return true;
}

int run_export(const ExportOptions& o) {
  if (core::mission_language(o.mission) != core::MissionLanguage::Coral) {
    std::cerr << fmt::format("strata export: '{}' is not a CORAL mission (.coral); PROLOG rules are not nets\n",
                             o.mission);
    return kExitUsage;
  }
  auto catalogue = load_catalogue_option(o.catalogue);
  if (!catalogue) {
    std::cerr << "strata export: " << catalogue.error().message << "\n";
    return exit_code_for_input(catalogue.error());
  }
  run::CoralLoad load = run::load_coral_file(o.mission, catalogue.value());
  if (int code = print_coral_load(std::cerr, load, "strata export"); code != kExitOk) return code;
  const coral::Program& program = *load.program;

  std::vector<const coral::CompiledNet*> nets;
  if (!o.net.empty()) {
    const coral::CompiledNet* n = program.find(o.net);
    if (!n) {
      std::cerr << fmt::format("strata export: no net '{}' in {}; its nets: {}\n", o.net, o.mission,
                               net_names(program));
      return kExitUsage;
    }
    nets.push_back(n);
  } else {
    for (const auto& n : program.nets) nets.push_back(&n);
  }
  // The nets `strata verify` explores: a PHASE's outcomes are the exits its
  // phase can reach.
  const std::vector<coral::PhaseExits> exits = coral::reachable_phase_exits(coral::verify_program(program));
  auto text = [&](const coral::CompiledNet& n) {
    return o.pnml ? coral::export_pnml(program, n, exits) : coral::export_dot(program, n, exits);
  };

  if (nets.size() == 1) {
    if (o.output.empty() || o.output == "-") {
      std::cout << text(*nets[0]);
      return kExitOk;
    }
    fs::path out = o.output;
    if (fs::is_directory(out)) out /= nets[0]->name + (o.pnml ? ".pnml" : ".dot");
    return write_file(out, text(*nets[0])) ? kExitOk : kExitIo;
  }
  if (o.output.empty() || o.output == "-") {
    std::cerr << fmt::format("strata export: {} holds {} nets: give -o FOLDER for one file each, or --net NAME\n",
                             o.mission, nets.size());
    return kExitUsage;
  }
  std::error_code ec;
  fs::create_directories(o.output, ec);
  if (ec || !fs::is_directory(o.output)) {
    std::cerr << fmt::format("strata export: cannot make the folder {}: {}\n", o.output,
                             ec ? ec.message() : "a file of that name exists");
    return kExitIo;
  }
  for (const auto* n : nets) {
    if (!write_file(fs::path(o.output) / (n->name + (o.pnml ? ".pnml" : ".dot")), text(*n))) return kExitIo;
  }
  return kExitOk;
}

}  // namespace

Runner add_export_command(CLI::App& app) {
  auto o = std::make_shared<ExportOptions>();
  auto* cmd = app.add_subcommand(
      "export",
      "Write a CORAL mission's nets for other tools: PNML (the analysis net `strata verify` explores) or "
      "Graphviz DOT");
  cmd->add_option("mission", o->mission, "A CORAL mission or library (.coral)")->required();
  auto* pnml = cmd->add_flag("--pnml", o->pnml, "PNML 2009 P/T nets (ISO/IEC 15909-2)");
  auto* dot = cmd->add_flag("--dot", o->dot, "Graphviz DOT (render with `dot -Tsvg`)");
  pnml->excludes(dot);
  dot->excludes(pnml);
  cmd->add_option("--net", o->net, "Only this net");
  cmd->add_option("-o,--output", o->output,
                  "A file for one net (default: standard output), a folder for several (one NAME.pnml or "
                  "NAME.dot each; made if missing)");
  cmd->add_option("--catalogue", o->catalogue, "Primitive catalogue (default: built in)");
  return [o] {
    if (!o->pnml && !o->dot) {
      std::cerr << "strata export: choose --pnml or --dot\n";
      return static_cast<int>(kExitUsage);
    }
    return run_export(*o);
  };
}

}  // namespace strata::cli
