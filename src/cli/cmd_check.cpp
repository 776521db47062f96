#include <iostream>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/mission_files.h"
#include "cli/rule_load_flags.h"
#include "cli/verbosity.h"
#include "coral/compiler.h"
#include "strategic/prolog_mission.h"
#include "run/loaded_mission.h"
#include "strategic/coral_catalogue.h"
#include "core/diagnostic_printer.h"
#include "core/mission_language.h"
#include "tactical/execution_level.h"

namespace strata::cli {
namespace {

struct CheckOptions {
  std::vector<std::string> files;
  std::string catalogue;
  std::string format = "text";
  std::string net;
  std::string vehicle;  // `strata run --vehicle`'s value: imc://... checks for an IMC vehicle
  run::RuleLoadLimits rule_load;
  VerbosityFlags verbosity;
};

// What makes two diagnostics the same problem: its file, place, kind and text.
using DiagnosticKey = std::tuple<std::string, std::uint32_t, int, std::string>;

DiagnosticKey key_of(const core::SourceManager& sources, const core::Diagnostic& d) {
  std::string path = d.span.file < sources.size() ? sources.path(d.span.file) : "";
  return {std::move(path), d.span.offset, static_cast<int>(d.kind), d.message};
}

// A file's errors and warnings, each problem once: a file its rules load
// twice says the same thing twice, and the report shows it once.
struct Counts {
  std::size_t errors = 0, warnings = 0;
};
Counts distinct_counts(const core::SourceManager& sources, const core::DiagnosticSink& sink) {
  std::set<DiagnosticKey> seen;
  Counts counts;
  for (const auto& d : sink.diagnostics()) {
    if (!seen.insert(key_of(sources, d)).second) continue;
    if (d.severity == core::Severity::Error) ++counts.errors;
    if (d.severity == core::Severity::Warning) ++counts.warnings;
  }
  return counts;
}

// Diagnostics of all roots, with a problem found through two roots (a phase
// file checked alone and through the mission that imports it) shown once.
class Report {
 public:
  explicit Report(std::string_view command) : command_(command) {}
  void add(const core::SourceManager& sources, const core::DiagnosticSink& sink) {
    for (const auto& d : sink.diagnostics()) {
      if (!seen_.insert(key_of(sources, d)).second) continue;
      if (d.severity == core::Severity::Error) ++errors_;
      if (d.severity == core::Severity::Warning) ++warnings_;
      if (d.kind == core::DiagnosticKind::FileUnreadable && d.span.file >= sources.size()) {
        unreadable_root_ = true;
      }
      json_.push_back(core::diagnostics_to_json(sources, std::span(&d, 1))[0]);
      core::print_diagnostic(text_, sources, d, command_);
    }
  }
  std::size_t errors() const { return errors_; }
  std::size_t warnings() const { return warnings_; }
  bool unreadable_root() const { return unreadable_root_; }
  std::string text() const { return text_.str(); }
  const nlohmann::json& json() const { return json_; }

 private:
  std::string_view command_;
  std::set<DiagnosticKey> seen_;
  std::size_t errors_ = 0, warnings_ = 0;
  bool unreadable_root_ = false;
  std::ostringstream text_;
  nlohmann::json json_ = nlohmann::json::array();
};

int exit_code_for(const Report& report) {
  if (report.unreadable_root()) return kExitIo;
  return report.errors() > 0 ? kExitInvalid : kExitOk;
}

std::string plural(std::size_t n, std::string_view word) { return fmt::format("{} {}{}", n, word, n == 1 ? "" : "s"); }

// A problem before any file is checked: the command's line for people, or
// with --format json the same as {"error": ...} on stdout, for tools.
int refuse(const CheckOptions& o, std::string_view command, const std::string& message, int code) {
  if (o.format == "json") {
    std::cout << core::dump_json({{"error", message}, {"diagnostics", nlohmann::json::array()}}) << "\n";
  } else {
    std::cerr << command << ": " << message << "\n";
  }
  return code;
}

int run_check(const CheckOptions& o) {
  auto catalogue = load_catalogue_option(o.catalogue);
  if (!catalogue) return refuse(o, "strata check", catalogue.error().message, exit_code_for_input(catalogue.error()));
  const tactical::ExecutionLevel level = tactical::execution_level_of(o.vehicle);
  const coral::CheckOptions options = strategic::coral_check_options(catalogue.value(), level);
  coral::DiskFileProvider disk;
  Report report("strata check");
  nlohmann::json files = nlohmann::json::array();
  std::vector<std::string> summaries;
  bool rules_unreadable = false;
  for (const auto& file : o.files) {
    if (auto why = not_a_mission(file, {core::MissionLanguage::Coral, core::MissionLanguage::Prolog})) {
      return refuse(o, "strata check", why->message, why->exit_code);
    }
  }
  for (const auto& file : o.files) {
    if (core::mission_language(file) == core::MissionLanguage::Prolog) {
      // PROLOG rules: loaded and checked as `strata run` does (docs/prolog.md).
      core::SourceManager sources;
      core::DiagnosticSink sink;
      auto rules = strategic::PrologMission::load(file, catalogue.value(), sources, sink, run::load_limits(o.rule_load),
                                                  strategic::KeepRules::No, level);
      if (!rules && !sink.has_errors()) {  // a file it cannot read, or no driver: nothing reported yet
        core::Diagnostic* d =
            sink.report(rules.error().code == core::ErrorCode::Io ? core::DiagnosticKind::FileUnreadable
                                                                  : core::DiagnosticKind::PrologLoadError,
                        {sources.add(file, ""), 0, 0}, rules.error().message);
        if (d) d->precision = core::Precision::File;
      }
      if (!rules && rules.error().code == core::ErrorCode::Io) rules_unreadable = true;
      report.add(sources, sink);
      const Counts counts = distinct_counts(sources, sink);
      files.push_back(nlohmann::json{{"file", file},
                                     {"language", "prolog"},
                                     {"ok", rules.ok()},
                                     {"errors", counts.errors},
                                     {"warnings", counts.warnings}});
      summaries.push_back(rules ? fmt::format("{}: ok (PROLOG rules, mission {})", file, rules.value()->name())
                                : fmt::format("{}: {}", file, plural(counts.errors, "error")));
      if (rules && &file == &o.files.back()) rules.value()->leave_open_to_exit();
      continue;
    }
    core::SourceManager sources;
    core::DiagnosticSink sink;
    auto program = coral::compile_file(file, disk, sources, sink, options);
    sink.sort();
    report.add(sources, sink);
    const Counts counts = distinct_counts(sources, sink);
    std::size_t nets = program ? program->nets.size() : 0;
    std::size_t transitions = 0;
    if (program) {
      for (const auto& n : program->nets) transitions += n.net.transition_count();
    }
    files.push_back(nlohmann::json{{"file", file},
                                   {"language", "coral"},
                                   {"ok", program.has_value()},
                                   {"nets", nets},
                                   {"transitions", transitions},
                                   {"errors", counts.errors},
                                   {"warnings", counts.warnings}});
    summaries.push_back(
        program ? fmt::format("{}: ok ({}, {})", file, plural(nets, "net"), plural(transitions, "transition"))
                : fmt::format("{}: {}", file, plural(counts.errors, "error")));
  }
  if (o.format == "json") {
    nlohmann::json out = {
        {"diagnostics", report.json()}, {"files", files}, {"errors", report.errors()}, {"warnings", report.warnings()}};
    std::cout << core::dump_json(out) << "\n";
  } else {
    std::cerr << report.text();
    // Quiet: the diagnostics and the totals, not a line per file.
    if (o.verbosity.level() != Verbosity::Quiet) {
      for (const auto& s : summaries) std::cout << s << "\n";
    }
    if (report.errors() + report.warnings() > 0) {
      std::cout << plural(report.errors(), "error") << ", " << plural(report.warnings(), "warning") << "\n";
    }
  }
  // Every file with an error: one line that says so, in the command's voice.
  for (const auto& f : files) {
    if (o.format == "json" || f["errors"].get<std::size_t>() == 0) continue;
    std::cerr << fmt::format("strata check: {}: {} (above, each at its place); fix and check again\n",
                             f["file"].get<std::string>(), plural(f["errors"].get<std::size_t>(), "error"));
  }
  if (rules_unreadable) return kExitIo;
  return exit_code_for(report);
}

int run_dump(const CheckOptions& o) {
  if (core::mission_language(o.files.front()) == core::MissionLanguage::Prolog) {
    return refuse(o, "strata dump",
                  fmt::format("'{}' holds PROLOG rules, not nets: dump prints a CORAL mission's nets (`strata check` "
                              "checks rules)",
                              o.files.front()),
                  kExitUsage);
  }
  if (auto why = not_a_mission(o.files.front(), {core::MissionLanguage::Coral})) {
    return refuse(o, "strata dump", why->message, why->exit_code);
  }
  auto catalogue = load_catalogue_option(o.catalogue);
  if (!catalogue) return refuse(o, "strata dump", catalogue.error().message, exit_code_for_input(catalogue.error()));
  coral::DiskFileProvider disk;
  core::SourceManager sources;
  core::DiagnosticSink sink;
  auto program =
      coral::compile_file(o.files.front(), disk, sources, sink, strategic::coral_check_options(catalogue.value()));
  sink.sort();
  Report report("strata dump");
  report.add(sources, sink);
  if (o.format == "json") {
    if (!program) std::cout << core::dump_json({{"diagnostics", report.json()}}) << "\n";
  } else {
    std::cerr << report.text();
  }
  if (!program) {
    if (o.format != "json")
      std::cerr << fmt::format("strata dump: {}: {}; no net to dump (`strata check` says the same)\n", o.files.front(),
                               plural(report.errors(), "error"));
    return exit_code_for(report);
  }
  if (!o.net.empty()) {
    const auto* n = program->find(o.net);
    if (!n) {
      std::cerr << fmt::format("strata dump: no net '{}' in {}; its nets: {}\n", o.net, o.files.front(),
                               net_names(*program));
      return kExitUsage;
    }
    std::cout << coral::dump_net(*n);
  } else {
    std::cout << coral::dump_program(*program);
  }
  return kExitOk;
}

}  // namespace

Runner add_check_command(CLI::App& app) {
  auto o = std::make_shared<CheckOptions>();
  auto* cmd = app.add_subcommand("check", "Check mission files (CORAL nets, PROLOG rules) and report diagnostics");
  cmd->add_option("files", o->files,
                  "Mission files: .coral (each checked with its imports) or .pl (loaded and checked as strata run "
                  "does)")
      ->required();
  cmd->add_option("--format", o->format, "Output format: text (for people) or json (for tools)")
      ->check(CLI::IsMember({"text", "json"}))
      ->capture_default_str();
  cmd->add_option("--catalogue", o->catalogue, "Primitive catalogue to check TACTIC calls against (default: built in)");
  cmd->add_option("--vehicle", o->vehicle,
                  "Check for the vehicle `strata run --vehicle` names: imc://HOST:PORT refuses, at each call, the "
                  "primitives an IMC vehicle cannot carry out (PrimitiveUnavailable); HOST:PORT, PORT or embedded "
                  "(the default) the Phoenix protocol, which carries them all");
  add_rule_load_flags(cmd, o->rule_load);
  cmd->footer(
      "Exit 0 when every file is clean of errors (warnings allowed), 65 on any error,\n"
      "74 when a file cannot be read.");
  add_verbosity_flags(cmd, o->verbosity, "");
  return [o] { return run_check(*o); };
}

Runner add_dump_command(CLI::App& app) {
  auto o = std::make_shared<CheckOptions>();
  auto* cmd = app.add_subcommand("dump", "Print the compiled Petri nets and action tables of a CORAL mission");
  cmd->add_option("file", o->files, "Mission file (.coral)")->required()->expected(1);
  cmd->add_option("--net", o->net, "Print only this net");
  cmd->add_option("--catalogue", o->catalogue, "Primitive catalogue (default: built in)");
  cmd->add_option("--format", o->format, "Diagnostics format: text or json")
      ->check(CLI::IsMember({"text", "json"}))
      ->capture_default_str();
  return [o] { return run_dump(*o); };
}

}  // namespace strata::cli
