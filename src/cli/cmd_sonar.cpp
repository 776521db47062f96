// `strata sonar --stream HOST:PORT --out DIR`: the Sonar Manager (paper
// §2.2, docs/sonar.md) — the vehicle's sonar stream captured on its own
// socket, drawn as scan images and searched for walls and a target.
#include <pthread.h>
#include <signal.h>

#include <atomic>
#include <iostream>
#include <memory>
#include <stop_token>
#include <thread>

#include "cli/validators.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/verbosity.h"
#include "sonar/manager.h"

namespace strata::cli {
namespace {

struct SonarOptions {
  std::string stream;
  std::string vehicle;  // the old spelling of --stream
  std::string out;
  int size_px = 400;
  double connect_timeout_s = 10.0;
  VerbosityFlags verbosity;
};

int run_sonar(const SonarOptions& o) {
  if (o.stream.empty() == o.vehicle.empty()) {
    std::cerr << "strata sonar: "
              << (o.stream.empty() ? "--stream ADDRESS:PORT is required"
                                   : "give --stream alone (--vehicle is its old name)")
              << "\n";
    return kExitUsage;
  }
  if (!o.vehicle.empty()) {
    std::cerr << "strata sonar: note: --vehicle is now --stream ADDRESS:PORT; the old name goes in a later release\n";
  }
  const std::string& address = o.stream.empty() ? o.vehicle : o.stream;
  auto endpoint = parse_listen(address);
  if (!endpoint) {
    std::cerr << "strata sonar: --stream: " << endpoint.error().message << "\n";
    return kExitUsage;
  }
  if (endpoint.value().second == 0) {
    std::cerr << "strata sonar: --stream needs the sonar stream's port (ADDRESS:PORT or PORT)\n";
    return kExitUsage;
  }
  sonar::ManagerOptions mo;
  mo.capture.host = endpoint.value().first;
  mo.capture.port = endpoint.value().second;
  mo.capture.connect_timeout_s = o.connect_timeout_s;
  mo.out_dir = o.out;
  mo.processor.image.size_px = o.size_px;
  mo.verbose = o.verbosity.level() == Verbosity::Verbose;
  mo.quiet = o.verbosity.level() == Verbosity::Quiet;
  // The manager's lines start "sonar: "; here they are the command's own.
  mo.log = [](const std::string& line) { std::cerr << "strata " << line << std::endl; };

  // SIGINT and SIGTERM are taken by a watcher thread (blocked here before any
  // thread starts, so no other thread receives them): it asks the manager to
  // stop, which writes the sweep under way and the summary.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  sigset_t previous;
  pthread_sigmask(SIG_BLOCK, &stop_signals, &previous);
  std::stop_source stop;
  std::atomic<int> signal_number{0};
  std::atomic<bool> finished{false};
  std::thread watcher([&] {
    while (!finished.load()) {
      const timespec wait{0, 100'000'000};
      const int s = sigtimedwait(&stop_signals, nullptr, &wait);
      if (s > 0) {
        signal_number = s;
        stop.request_stop();
        return;
      }
    }
  });
  const sonar::ManagerSummary summary = sonar::run_sonar_manager(mo, stop.get_token());
  finished = true;
  watcher.join();
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  if (summary.outcome == sonar::Outcome::Stopped && signal_number.load() != 0) return 128 + signal_number.load();
  return summary.exit_code;
}

}  // namespace

Runner add_sonar_command(CLI::App& app) {
  auto o = std::make_shared<SonarOptions>();
  auto* cmd = app.add_subcommand(
      "sonar",
      "The Sonar Manager: capture the vehicle's sonar stream, write scan images (PNG) and the walls and target "
      "it sees (JSON lines) into a folder");
  cmd->add_option(
      "--stream", o->stream,
      "ADDRESS:PORT or PORT (address 127.0.0.1) of the vehicle's sonar stream (`strata vehicle` prints it)");
  cmd->add_option("--vehicle", o->vehicle, "Old spelling of --stream")->group("");
  cmd->add_option("--out", o->out,
                  "Folder for scan_NNNNN.png (one per sweep), latest.png (the newest) and sonar.jsonl; made if missing")
      ->required();
  cmd->add_option("--size", o->size_px, "Width and height of the images in pixels (the sonar's range is half of it)")
      ->check(CLI::Range(64, 4096))
      ->capture_default_str();
  cmd->add_option("--connect-timeout", o->connect_timeout_s,
                  "Seconds to keep retrying while the vehicle refuses the connection")
      ->check(finite_range(0.0, 3600.0))
      ->capture_default_str();
  add_verbosity_flags(cmd, o->verbosity, "A line on stderr for each frame written");
  cmd->footer(
      "Example (the vehicle's sonar stream on port 7021; the studio shows sonar/latest.png):\n"
      "  strata sonar --stream 127.0.0.1:7021 --out sonar/ --verbose\n"
      "It prints a line when connected and a summary at the end (stderr); frames go to the folder.\n"
      "Exit: 0 when the vehicle ended the stream (also when the sonar never started); 69 when the vehicle "
      "could not be reached within --connect-timeout or went away without ending the stream; 74 when the "
      "folder cannot be written; 130/143 after SIGINT/SIGTERM (the sweep under way and the summary are "
      "written first); 64 for a bad command line.");
  return [o] { return run_sonar(*o); };
}

}  // namespace strata::cli
