// `strata completion bash|zsh` (a completion script on stdout) and the
// hidden `strata manpages DIR` the build uses to write the man pages.
#include <sys/stat.h>

#include <ctime>
#include <filesystem>
#include <iostream>
#include <memory>
#include <vector>

#include "cli/cli_docs.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/pnml_verify.h"
#include "core/file.h"

namespace strata::cli {
namespace {

namespace fs = std::filesystem;

std::string today() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[16];
  std::strftime(buf, sizeof buf, "%Y-%m-%d", &tm);
  return buf;
}

// Writes each (file name, text) into dir, created if missing.
int write_files(const std::string& dir, const std::vector<GeneratedFile>& files) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    std::cerr << "strata manpages: cannot create the folder " << dir << (ec ? ": " + ec.message() : "") << "\n";
    return kExitIo;
  }
  for (const auto& f : files) {
    // A link at a page's name is refused, not written through.
    if (auto written = core::write_file_atomically((fs::path(dir) / f.file).string(), f.text); !written) {
      std::cerr << "strata manpages: " << written.error().message << "\n";
      return kExitIo;
    }
  }
  return kExitOk;
}

}  // namespace

Runner add_docs_commands(CLI::App& app, const std::string& version) {
  auto shell = std::make_shared<std::string>();
  auto* completion = app.add_subcommand(
      "completion", "Print a shell completion script: `source <(strata completion bash)`, or install it (see docs)");
  completion->add_option("shell", *shell, "bash or zsh")->required()->check(CLI::IsMember({"bash", "zsh"}));

  struct Pages {
    std::string dir;
    std::string date;
    std::string completions;
  };
  auto pages = std::make_shared<Pages>();
  auto* manpages =
      app.add_subcommand("manpages", "Write the man pages (strata.1, strata-COMMAND.1, strata-pnml.1) into a folder");
  manpages->group("");  // hidden: the build's tool (cmake/install.cmake)
  manpages->add_option("dir", pages->dir, "The folder")->required();
  manpages->add_option("--date", pages->date, "The pages' date (default: today, UTC)");
  manpages->add_option("--completions", pages->completions,
                       "Also write the completion scripts strata.bash and _strata (zsh), and strata-pnml's, into "
                       "this folder");

  return [&app, shell, pages, completion, version] {
    if (completion->parsed()) {
      std::cout << (*shell == "bash" ? bash_completion(app) : zsh_completion(app));
      return static_cast<int>(kExitOk);
    }
    const std::string date = pages->date.empty() ? today() : pages->date;
    std::vector<GeneratedFile> written = man_pages(app, version, date);
    // strata-pnml's page and completions, from its own command line (cli/pnml_verify.h).
    const PnmlCommandLine pnml(version);
    for (GeneratedFile& page : man_pages(pnml.app, version, date)) written.push_back(std::move(page));
    const int rc = write_files(pages->dir, written);
    if (rc != kExitOk || pages->completions.empty()) return rc;
    return write_files(pages->completions, {{"strata.bash", bash_completion(app)},
                                            {"_strata", zsh_completion(app)},
                                            {"strata-pnml.bash", bash_completion(pnml.app)},
                                            {"_strata-pnml", zsh_completion(pnml.app)}});
  };
}

}  // namespace strata::cli
