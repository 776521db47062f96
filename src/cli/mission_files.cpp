#include "cli/mission_files.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

namespace strata::cli {

std::optional<NotAMission> not_a_mission(const std::string& path,
                                         std::initializer_list<core::MissionLanguage> languages) {
  const core::MissionLanguage language = core::mission_language(path);
  bool known = false;
  std::string wanted;
  for (auto l : languages) {
    known = known || language == l;
    wanted += fmt::format("{}{} ({})", wanted.empty() ? "" : " or ", core::mission_extension(l),
                          l == core::MissionLanguage::Prolog ? "PROLOG rules" : "a CORAL mission");
  }
  if (!known) {
    const std::string ext = std::filesystem::path(path).extension().string();
    std::string what = ext == ".toml"    ? " (a scenario, parameter, catalogue or mission-data file?)"
                       : ext == ".jsonl" ? " (a mission log?)"
                       : ext == ".pnml"  ? " (a P/T net: `strata verify --pnml`)"
                                         : "";
    return NotAMission{fmt::format("'{}' is not a mission file{}: this command takes {}", path, what, wanted), 64};
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;  // the parser says what it is
  std::ifstream in(path, std::ios::binary);
  char head[4096];
  in.read(head, sizeof head);
  const std::string_view bytes(head, static_cast<std::size_t>(in.gcount()));
  if (const auto nul = bytes.find('\0'); nul != std::string_view::npos) {
    const std::string_view before = bytes.substr(0, nul);
    const std::size_t line = 1 + static_cast<std::size_t>(std::count(before.begin(), before.end(), '\n'));
    const std::size_t col = nul - (before.rfind('\n') == std::string_view::npos ? 0 : before.rfind('\n') + 1) + 1;
    return NotAMission{fmt::format("{}:{}:{}: not text (a NUL byte): not a mission file", path, line, col), 65};
  }
  return std::nullopt;
}

std::string net_names(const coral::Program& program) {
  std::string out;
  for (const auto& n : program.nets) out += (out.empty() ? "" : ", ") + n.name;
  return out;
}

}  // namespace strata::cli
