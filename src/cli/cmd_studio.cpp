// `strata studio [DIR]`: the graphical editor and live view, in the browser
// (docs/studio.md). `strata run MISSION --studio` uses serve_studio_run().
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/console.h"
#include "cli/run_problems.h"
#include "cli/signal_watcher.h"
#include "cli/studio_serve.h"
#include "cli/user_config.h"
#include "cli/verbosity.h"
#include "studio/assets.h"
#include "studio/http_module.h"
#include "studio/studio_runner.h"

namespace strata::cli {
namespace {

namespace fs = std::filesystem;

struct StudioOptions {
  std::string dir = ".";
  std::string listen = "127.0.0.1:0";
  std::optional<std::string> host;    // old spelling: --host ADDRESS
  std::optional<std::uint16_t> port;  // old spelling: --port PORT
  std::string web_root;
  std::string catalogue;
  std::string sonar;
  bool no_sonar = false;
  int max_streams = studio::StudioOptions{}.max_streams;
  int max_verifies = studio::StudioOptions{}.max_verifies;
  VerbosityFlags verbosity;
};

// --listen, or the old --host/--port (a note says so): the address to bind.
core::Result<std::pair<std::string, std::uint16_t>> studio_endpoint(const StudioOptions& o, bool listen_given) {
  if (!o.host && !o.port) return parse_listen(o.listen);
  if (listen_given) {
    return core::make_error(core::ErrorCode::InvalidInput, "give --listen alone (--host and --port are its old names)");
  }
  std::cerr << "strata studio: note: --host and --port are now --listen ADDRESS:PORT; the old names go in a later "
               "release\n";
  return parse_listen(fmt::format("{}:{}", o.host.value_or("127.0.0.1"), o.port.value_or(0)));
}

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

int run_studio(const StudioOptions& o, bool listen_given) {
  std::error_code ec;
  auto endpoint = studio_endpoint(o, listen_given);
  if (!endpoint) {
    std::cerr << "strata studio: " << endpoint.error().message << "\n";
    return kExitUsage;
  }
  const std::string host = endpoint.value().first;
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
  so.host = host;
  so.port = endpoint.value().second;
  if (o.verbosity.level() == Verbosity::Verbose) {
    so.request_log = [](const std::string& line) { std::cerr << ("strata studio: " + line + "\n") << std::flush; };
  }
  so.web_root = o.web_root;
  so.catalogue = &catalogue.value();
  so.max_streams = o.max_streams;
  so.max_verifies = o.max_verifies;
  // Runs started from the page get a Sonar Manager writing here; the page
  // shows its newest scan.
  if (!o.no_sonar) {
    if (o.sonar.empty()) {
      // A folder of our own (mkdtemp: a fresh name, mode 0700). A name made
      // from the pid could be made first by another user of the machine, as
      // a folder holding links at the names the sonar writes.
      std::string pattern = (fs::temp_directory_path() / "strata-studio-sonar-XXXXXX").string();
      if (::mkdtemp(pattern.data()) == nullptr) {
        std::cerr << fmt::format(
            "strata studio: cannot make a folder for the sonar's scans in {}: {} (--sonar DIR, "
            "or --no-sonar)\n",
            fs::temp_directory_path().string(), std::strerror(errno));
        return kExitIo;
      }
      so.sonar_dir = pattern;
    } else {
      so.sonar_dir = fs::path(o.sonar);
    }
  }
  // Our own temporary folder goes whichever way the studio ends.
  const auto remove_own_sonar = [&] {
    if (!o.no_sonar && o.sonar.empty()) fs::remove_all(so.sonar_dir, ec);
  };
  // Runs started from the page: the run library on a thread of its own.
  studio::StudioRunner runner(hub, sandbox, catalogue.value());
  runner.set_sonar_dir(so.sonar_dir.string());
  so.runs = &runner;
  auto server = studio::make_http_server(so, hub);
  if (!server) {
    std::cerr << "strata studio: " << server.error().message << "\n";
    remove_own_sonar();
    return kExitUnavailable;
  }
  auto port = server.value()->start();
  if (!port) {
    std::cerr << "strata studio: " << port.error().message << "\n";
    remove_own_sonar();
    return kExitIo;
  }
  std::cout << fmt::format("http://{}:{}", host, port.value()) << std::endl;
  const bool quiet = o.verbosity.level() == Verbosity::Quiet;
  if (!quiet) {
    std::cerr << fmt::format(
        "strata studio: serving {} (Ctrl-C to stop){}\n", sandbox.root().string(),
        o.web_root.empty() && !server.value()->page_built() ? "; the page was not built into this strata" : "");
  }
  int signal = 0;
  sigwait(&stop_signals, &signal);
  if (!quiet) std::cerr << "strata studio: stopping\n";
  runner.abort();  // a run going ends through its safe end first
  server.value()->stop();
  remove_own_sonar();
  return kExitOk;
}

}  // namespace

RunReport serve_studio_run(RunOptions options, const std::string& host, std::uint16_t port, const StudioRunWait& wait,
                           std::ostream& out, std::ostream& err) {
  // Before the server's threads start, so that they inherit the mask and the
  // SignalWatcher below alone takes Ctrl-C (else a signal during the run
  // reaches an HTTP thread and ends the process with the vehicle at depth).
  block_stop_signals();
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
  auto server = studio::make_http_server(so, hub);
  if (!server) {
    err << "strata run: --studio: " << server.error().message << "\n";
    failed.exit_code = kExitUnavailable;
    return failed;
  }
  auto bound = server.value()->start();
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
    report = runner.run_here(request, options, {&console},
                             [&](const run::LoadedMission& loaded) { print_load_findings(err, loaded, options); });
  }
  print_run_errors(err, report);
  out << run::summary_text(report);
  if (wait.seconds ? *wait.seconds > 0 : wait.terminal) {
    const sigset_t stop_signals = block_stop_signals();
    out << fmt::format("the run is over; still serving http://{}:{} ({}Ctrl-C to quit)", host, bound.value(),
                       wait.seconds ? fmt::format("for {:g} s; ", *wait.seconds) : "")
        << std::endl;
    if (wait.seconds) {
      const double whole = std::floor(*wait.seconds);
      const timespec timeout{static_cast<time_t>(whole), static_cast<long>((*wait.seconds - whole) * 1e9)};
      sigtimedwait(&stop_signals, nullptr, &timeout);
    } else {
      int signal = 0;
      sigwait(&stop_signals, &signal);
    }
  }
  server.value()->stop();
  return report;
}

Runner add_studio_command(CLI::App& app, const LoadedConfig& config) {
  auto o = std::make_shared<StudioOptions>();
  o->listen = config.config.studio_listen.value;
  auto* cmd = app.add_subcommand("studio",
                                 "Serve the graphical mission editor and the live view of runs in the browser "
                                 "(prints http://127.0.0.1:PORT first)");
  cmd->add_option("dir", o->dir, "The folder whose missions it may read and write (default: the current one)");
  cmd->add_option("--listen", o->listen,
                  "ADDRESS:PORT or PORT to listen on (0: a free port; the address is the first line printed)")
      ->capture_default_str();
  cmd->add_option("--port", o->port, "Old spelling of --listen PORT")->group("");
  cmd->add_option("--host", o->host, "Old spelling of --listen ADDRESS:PORT")->group("");
  cmd->add_option("--web-root", o->web_root, "Serve the page from this folder (web/dist) instead of the built-in one");
  cmd->add_option("--catalogue", o->catalogue, "Primitive catalogue (default: built in)");
  cmd->add_option("--sonar", o->sonar,
                  "Where the Sonar Manager of a run started from the page writes its scans (default: a folder in "
                  "the system's temporary folder)");
  cmd->add_flag("--no-sonar", o->no_sonar, "Runs started from the page get no Sonar Manager");
  cmd->add_option("--max-streams", o->max_streams,
                  "Live-view event streams open at once, from every tab (each holds a worker; past it: 503)")
      ->check(CLI::Range(1, 32))
      ->capture_default_str();
  cmd->add_option("--max-verifies", o->max_verifies,
                  "Verifications running at once (each may take its memory limit; past it: 429)")
      ->check(CLI::Range(1, 8))
      ->capture_default_str();
  cmd->footer(
      "docs/studio.md has the page's API. Exit 0 after Ctrl-C; 69 when its HTTP module (libstrata_studio_http.so) is "
      "missing; 74 when it cannot listen or read DIR.");
  add_verbosity_flags(cmd, o->verbosity, "Also a line on stderr for each request answered");
  return [o, cmd, &config] {
    if (auto failed = config_failure(config, "studio")) return *failed;
    return run_studio(*o, cmd->count("--listen") > 0);
  };
}

}  // namespace strata::cli
