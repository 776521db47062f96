#pragma once
// Man pages and shell completion written from the CLI's own definition (the
// CLI11 App tree), so they cannot drift from `--help`:
//
//   strata.1            the command, its subcommands, its exit codes
//   strata-NAME.1       one per subcommand: arguments, options, exit codes
//   bash and zsh        subcommands, each one's options, files elsewhere
//
// `strata completion bash|zsh` prints a completion script; the build writes
// the man pages with the hidden `strata manpages DIR` (cmake/install.cmake).
// Hidden subcommands and options (an empty group) are left out.
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

namespace strata::cli {

struct GeneratedFile {
  std::string file;  // its name: "strata.1", "strata-run.1", "strata.bash"
  std::string text;
};

// Every page: strata.1 first, then one per visible subcommand. date: the
// page's date as it appears in its header (e.g. "2026-11-26").
std::vector<GeneratedFile> man_pages(const CLI::App& root, std::string_view version, std::string_view date);

std::string bash_completion(const CLI::App& root);
std::string zsh_completion(const CLI::App& root);

// Text made safe for roff: backslashes, leading dots and quotes, hyphens.
std::string roff_escape(std::string_view text);

}  // namespace strata::cli
