#include "cli/usage_hints.h"

#include <string_view>

#include <fmt/format.h>

#include "core/text.h"

namespace strata::cli {
namespace {

std::vector<std::string> visible_commands(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* s : app.get_subcommands([](const CLI::App* a) { return !a->get_group().empty(); })) {
    names.push_back(s->get_name());
  }
  return names;
}

// "--name" and "-n" spellings of app's options (and its parent's, which a
// subcommand accepts too: --help).
std::vector<std::string> option_spellings(const CLI::App& app) {
  std::vector<std::string> out;
  for (const CLI::App* a = &app; a != nullptr; a = a->get_parent()) {
    for (const CLI::Option* o : a->get_options()) {
      for (const auto& l : o->get_lnames()) out.push_back("--" + l);
      for (const auto& s : o->get_snames()) out.push_back("-" + s);
    }
  }
  return out;
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// The deepest command argv names (`config show`), or app itself.
const CLI::App* named_command(const CLI::App& app, int argc, const char* const* argv) {
  const CLI::App* at = &app;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg.empty() || arg[0] == '-') continue;
    const CLI::App* next = nullptr;
    for (const CLI::App* s : at->get_subcommands([](const CLI::App*) { return true; })) {
      if (s->check_name(std::string(arg))) next = s;
    }
    if (next == nullptr) break;  // an argument of the command found so far
    at = next;
  }
  return at;
}

// "PATH: unknown option '--nte': did you mean '--net'?" for each option
// from argv[from] on that command does not know, and where to look.
std::vector<std::string> unknown_options(const CLI::App& command, const std::string& path, int from, int argc,
                                         const char* const* argv) {
  std::vector<std::string> hints;
  const std::vector<std::string> known = option_spellings(command);
  for (int i = from; i < argc; ++i) {
    std::string_view arg = argv[i];
    if (arg == "--") break;
    if (arg.size() < 2 || arg[0] != '-' || (arg[1] >= '0' && arg[1] <= '9') || arg[1] == '.') continue;
    if (arg.substr(0, 2) != "--" && arg.size() > 2) continue;  // -abc: short flags together, left to CLI11
    const std::string name(arg.substr(0, arg.find('=')));
    bool found = false;
    for (const auto& k : known) found = found || k == name;
    if (found) continue;
    std::string hint = fmt::format("{}: unknown option '{}'", path, name);
    if (auto s = core::suggest(name, known)) hint += fmt::format(": did you mean '{}'?", *s);
    hints.push_back(hint);
  }
  if (!hints.empty()) hints.push_back(fmt::format("`{} --help` lists its options", path));
  return hints;
}

}  // namespace

std::vector<std::string> usage_hints(const CLI::App& app, int argc, const char* const* argv) {
  std::vector<std::string> hints;
  if (argc < 2) return hints;
  const std::string first = argv[1];
  // A program without commands (strata-pnml): its options from the first
  // argument on.
  const bool has_commands = !app.get_subcommands([](const CLI::App*) { return true; }).empty();
  if (!has_commands) return unknown_options(app, app.get_name(), 1, argc, argv);
  if (first.empty() || first[0] == '-') return hints;
  const CLI::App* sub = nullptr;
  for (const CLI::App* s : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (s->check_name(first)) sub = s;
  }
  const std::vector<std::string> commands = visible_commands(app);
  if (sub == nullptr) {
    std::string hint = fmt::format("{}: unknown command '{}'", app.get_name(), first);
    if (auto s = core::suggest(first, commands)) hint += fmt::format(": did you mean '{}'?", *s);
    hints.push_back(hint);
    hints.push_back("the commands: " + join(commands));
    return hints;
  }
  // The command the options belong to: `config show`'s, not `config`'s.
  const std::string path = command_path(app, argc, argv);
  return unknown_options(*named_command(app, argc, argv), path, 2, argc, argv);
}

std::string command_path(const CLI::App& app, int argc, const char* const* argv) {
  std::vector<std::string> names;
  for (const CLI::App* at = named_command(app, argc, argv); at != nullptr; at = at->get_parent()) {
    names.push_back(at->get_name());
  }
  std::string path;
  for (auto n = names.rbegin(); n != names.rend(); ++n) {
    if (!path.empty()) path += ' ';
    path += *n;
  }
  return path;
}

std::vector<std::string> usage_error(const CLI::App& app, const CLI::ParseError& error, int argc,
                                     const char* const* argv) {
  std::vector<std::string> lines = usage_hints(app, argc, argv);
  if (!lines.empty()) return lines;
  const std::string path = command_path(app, argc, argv);
  std::string what = error.what();
  if (path == app.get_name() && argc < 2 && !visible_commands(app).empty()) {
    lines.push_back(fmt::format("{}: give a command: {}", path, join(visible_commands(app))));
    lines.push_back(fmt::format("`{} --help` says what each does", path));
    return lines;
  }
  if (!what.empty() && what[0] >= 'A' && what[0] <= 'Z') what[0] = static_cast<char>(what[0] - 'A' + 'a');
  // A value's own message ("--speed: 'abc' is not a number") names its
  // option already; CLI11's tail ("Run with --help ...") is replaced below.
  lines.push_back(fmt::format("{}: {}", path, what));
  lines.push_back(fmt::format("`{} --help` lists its arguments and options", path));
  return lines;
}

}  // namespace strata::cli
