// `strata studio [DIR]`: the graphical editor and live view, in the browser
// (docs/studio.md). `strata run MISSION --studio` uses serve_studio_run().
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/console.h"
#include "cli/signal_watcher.h"
#include "cli/studio_serve.h"
#include "studio/assets.h"
#include "studio/server.h"
#include "studio/studio_runner.h"

namespace strata::cli {
namespace {

namespace fs = std::filesystem;

struct StudioOptions {
  std::string dir = ".";
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;
  std::string web_root;
  std::string catalogue;
  std::string sonar;
  bool no_sonar = false;
};

// SIGINT, SIGTERM and SIGHUP blocked in this thread and every thread it
// starts after, so that sigwait() alone receives them (a closed terminal
// stops the studio as Ctrl-C does: a run going ends through its safe end).
sigset_t block_stop_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  return set;
}

int run_studio(const StudioOptions& o) {
  std::error_code ec;
  if (!fs::is_directory(o.dir, ec)) {
    std::cerr << fmt::format("strata studio: '{}' is not a folder\n", o.dir);
    return kExitIo;
  }
  if (!o.web_root.empty() && !fs::exists(fs::path(o.web_root) / "index.html", ec)) {
    std::cerr << fmt::format("strata studio: --web-root '{}' has no index.html (build it: cd web && npm run build)\n",
                             o.web_root);
    return kExitIo;
  }
  auto catalogue = load_catalogue_option(o.catalogue);
  if (!catalogue) {
    std::cerr << "strata studio: " << catalogue.error().message << "\n";
    return exit_code_for_input(catalogue.error());
  }
  const sigset_t stop_signals = block_stop_signals();
  studio::EventHub hub;
  studio::Sandbox sandbox(o.dir);
  studio::StudioOptions so;
  so.root = o.dir;
  so.host = o.host;
  so.port = o.port;
  so.web_root = o.web_root;
  so.catalogue = &catalogue.value();
  // Runs started from the page get a Sonar Manager writing here; the page
  // shows its newest scan.
  if (!o.no_sonar) {
    so.sonar_dir = o.sonar.empty() ? fs::temp_directory_path() / fmt::format("strata-studio-{}-sonar", ::getpid())
                                   : fs::path(o.sonar);
  }
  studio::StudioServer server(so, hub);
  auto port = server.start();
  if (!port) {
    std::cerr << "strata studio: " << port.error().message << "\n";
    return kExitIo;
  }
  std::cout << fmt::format("http://{}:{}", o.host, port.value()) << std::endl;
  std::cerr << fmt::format(
      "strata studio: serving {} (Ctrl-C to stop){}\n", sandbox.root().string(),
      o.web_root.empty() && !studio::page_built() ? "; the page was not built into this strata" : "");
  int signal = 0;
  sigwait(&stop_signals, &signal);
  std::cerr << "strata studio: stopping\n";
  server.stop();                                                         // a run going ends through its safe end first
  if (!o.no_sonar && o.sonar.empty()) fs::remove_all(so.sonar_dir, ec);  // our own temporary folder
  return kExitOk;
}

}  // namespace

RunReport serve_studio_run(RunOptions options, const std::string& host, std::uint16_t port, std::ostream& out,
                           std::ostream& err) {
  RunReport failed;
  failed.exit_code = kExitIo;
  const fs::path mission = fs::absolute(options.mission);
  std::error_code ec;
  if (!fs::is_regular_file(mission, ec)) {
    err << fmt::format("strata run: cannot open '{}'\n", options.mission);
    return failed;
  }
  auto catalogue = load_catalogue_option(options.catalogue);
  if (!catalogue) {
    err << "strata run: " << catalogue.error().message << "\n";
    failed.exit_code = exit_code_for_input(catalogue.error());
    return failed;
  }
  studio::EventHub hub;
  studio::Sandbox sandbox(mission.parent_path());
  studio::StudioRunner runner(hub, sandbox, catalogue.value());
  studio::StudioOptions so;
  so.runs = &runner;
  so.root = mission.parent_path();
  so.host = host;
  so.port = port;
  so.catalogue = &catalogue.value();
  so.sonar_dir = options.sonar_dir;
  studio::StudioServer server(so, hub);
  auto bound = server.start();
  if (!bound) {
    err << "strata run: --studio: " << bound.error().message << "\n";
    return failed;
  }
  out << fmt::format("http://{}:{}", host, bound.value()) << std::endl;
  studio::RunRequest request{mission, mission.filename().string(), options.scenario, options.speed};
  Console console(out, /*tty=*/false);  // the page shows the status; the console keeps plain lines
  RunReport report;
  {
    SignalWatcher signals([&runner](int signal) {
      const std::string name = signal_name(signal);
      runner.stop(name, "interrupted by " + name, kExitSignalBase + signal);
    });
    report = runner.run_here(request, options, {&console}, err);
  }
  out << run::summary_text(report);
  if (isatty(STDIN_FILENO) == 1 && isatty(STDOUT_FILENO) == 1) {
    const sigset_t stop_signals = block_stop_signals();
    out << fmt::format("the run is over; still serving http://{}:{} (Ctrl-C to quit)", host, bound.value())
        << std::endl;
    int signal = 0;
    sigwait(&stop_signals, &signal);
  }
  server.stop();
  return report;
}

Runner add_studio_command(CLI::App& app) {
  auto o = std::make_shared<StudioOptions>();
  auto* cmd = app.add_subcommand("studio",
                                 "Serve the graphical mission editor and the live view of runs in the browser "
                                 "(prints http://127.0.0.1:PORT first)");
  cmd->add_option("dir", o->dir, "The folder whose missions it may read and write (default: the current one)");
  cmd->add_option("--port", o->port, "Port to listen on (0: a free one)")->capture_default_str();
  cmd->add_option("--host", o->host, "Address to listen on")->capture_default_str();
  cmd->add_option("--web-root", o->web_root, "Serve the page from this folder (web/dist) instead of the built-in one");
  cmd->add_option("--catalogue", o->catalogue, "Primitive catalogue (default: built in)");
  cmd->add_option("--sonar", o->sonar,
                  "Where the Sonar Manager of a run started from the page writes its scans (default: a folder in "
                  "the system's temporary folder)");
  cmd->add_flag("--no-sonar", o->no_sonar, "Runs started from the page get no Sonar Manager");
  cmd->footer("docs/studio.md has the page's API. Exit 0 after Ctrl-C; 74 when it cannot listen or read DIR.");
  return [o] { return run_studio(*o); };
}

}  // namespace strata::cli
