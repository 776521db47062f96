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

}  // namespace

std::vector<std::string> usage_hints(const CLI::App& app, int argc, const char* const* argv) {
  std::vector<std::string> hints;
  if (argc < 2) return hints;
  const std::string first = argv[1];
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
  const std::vector<std::string> known = option_spellings(*sub);
  for (int i = 2; i < argc; ++i) {
    std::string_view arg = argv[i];
    if (arg == "--") break;
    if (arg.size() < 2 || arg[0] != '-' || (arg[1] >= '0' && arg[1] <= '9') || arg[1] == '.') continue;
    if (arg.substr(0, 2) != "--" && arg.size() > 2) continue;  // -abc: short flags together, left to CLI11
    const std::string name(arg.substr(0, arg.find('=')));
    bool found = false;
    for (const auto& k : known) found = found || k == name;
    if (found) continue;
    std::string hint = fmt::format("{} {}: unknown option '{}'", app.get_name(), sub->get_name(), name);
    if (auto s = core::suggest(name, known)) hint += fmt::format(": did you mean '{}'?", *s);
    hints.push_back(hint);
  }
  if (!hints.empty()) hints.push_back(fmt::format("`{} {} --help` lists its options", app.get_name(), sub->get_name()));
  return hints;
}

}  // namespace strata::cli
