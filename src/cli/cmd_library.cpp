// `strata library`: the phases of the phase library (docs/library.md), each
// with its parameters and exits, from the folders `import NAME;` and
// `:- use_phase(NAME).` search.
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "coral/compiler.h"
#include "coral/loader.h"
#include "core/diagnostic_printer.h"
#include "strategic/coral_catalogue.h"
#include "tactical/catalogue.h"

namespace strata::cli {
namespace {

namespace fs = std::filesystem;

struct LibraryOptions {
  std::string format = "text";
};

// NAME -> the file a search for NAME takes: the first folder's.
std::map<std::string, std::string> modules_in(const std::vector<std::string>& dirs, const std::string& extension) {
  std::map<std::string, std::string> found;
  for (const auto& dir : dirs) {
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      if (it->path().extension() == extension && it->is_regular_file(ec)) {
        found.emplace(it->path().stem().string(), it->path().lexically_normal().string());
      }
    }
  }
  return found;
}

struct Phase {
  std::string name;
  std::vector<std::string> params;  // "x", or "string s"
  std::vector<std::string> exits;
  std::optional<std::string> coral, prolog;
};

std::string signature(const Phase& p) {
  std::string params;
  for (const auto& x : p.params) params += (params.empty() ? "" : ", ") + x;
  return p.params.empty() ? p.name : fmt::format("{}({})", p.name, params);
}

int run_library(const LibraryOptions& o) {
  const std::vector<std::string> coral_dirs = coral::library_dirs("coral");
  const std::vector<std::string> prolog_dirs = coral::library_dirs("prolog");
  std::map<std::string, Phase> phases;
  for (const auto& [name, path] : modules_in(prolog_dirs, ".pl")) {
    phases[name].name = name;
    phases[name].prolog = path;
  }
  int code = kExitOk;
  const auto catalogue = tactical::Catalogue::builtin();
  for (const auto& [name, path] : modules_in(coral_dirs, ".coral")) {
    Phase& p = phases[name];
    p.name = name;
    p.coral = path;
    core::SourceManager sources;
    core::DiagnosticSink sink;
    coral::DiskFileProvider disk;
    auto program = coral::compile_file(path, disk, sources, sink, strategic::coral_check_options(catalogue));
    if (sink.has_errors() || !program) {
      core::print_diagnostics(std::cerr, sources, sink.diagnostics());
      code = kExitInvalid;
      continue;
    }
    const coral::CompiledNet* net = nullptr;
    for (const auto& cn : program->nets) {
      if (cn.name == name && cn.kind == coral::ast::Net::Kind::Phase) net = &cn;
    }
    if (!net) {
      std::cerr << fmt::format("{}: error: declares no phase net '{}': `import {};` would find no phase of that name\n",
                               path, name, name);
      code = kExitInvalid;
      continue;
    }
    for (const auto& param : net->params) {
      p.params.push_back(param.type == coral::ast::ParamType::String ? "string " + param.name.text : param.name.text);
    }
    for (auto e : net->exits) p.exits.emplace_back(net->net.place_name(e));
  }

  if (o.format == "json") {
    nlohmann::json out = nlohmann::json::object();
    out["folders"] = {{"coral", coral_dirs}, {"prolog", prolog_dirs}};
    nlohmann::json list = nlohmann::json::array();
    for (const auto& [name, p] : phases) {
      nlohmann::json j = nlohmann::json::object();
      j["name"] = name;
      j["params"] = p.params;
      j["exits"] = p.exits;
      j["coral"] = p.coral ? nlohmann::json(*p.coral) : nlohmann::json();
      j["prolog"] = p.prolog ? nlohmann::json(*p.prolog) : nlohmann::json();
      list.push_back(std::move(j));
    }
    out["phases"] = std::move(list);
    std::cout << out.dump(2) << "\n";
    return code;
  }
  auto listed = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s.empty() ? std::string("(none)") : s;
  };
  std::cout << "CORAL (import NAME;): " << listed(coral_dirs) << "\n";
  std::cout << "PROLOG (:- use_phase(NAME).): " << listed(prolog_dirs) << "\n";
  for (const auto& [name, p] : phases) {
    std::cout << "\n" << (p.coral ? signature(p) : name + " (PROLOG only)");
    if (!p.exits.empty()) std::cout << "  exits: " << listed(p.exits);
    std::cout << "\n";
    if (p.coral) std::cout << "  " << *p.coral << "\n";
    if (p.prolog) std::cout << "  " << *p.prolog << "\n";
  }
  return code;
}

}  // namespace

Runner add_library_command(CLI::App& app) {
  auto o = std::make_shared<LibraryOptions>();
  auto* cmd = app.add_subcommand("library", "Print the phases of the phase library, their parameters and exits");
  cmd->add_option("--format", o->format, "text or json")->check(CLI::IsMember({"text", "json"}))->capture_default_str();
  return [o] { return run_library(*o); };
}

}  // namespace strata::cli
