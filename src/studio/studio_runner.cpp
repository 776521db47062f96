#include "studio/studio_runner.h"

#include <ext/stdio_filebuf.h>
#include <unistd.h>

#include <ctime>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>

#include "core/mission_language.h"
#include "studio/mission_model.h"
#include "studio/prolog_thread.h"
#include "studio/run_publisher.h"

namespace strata::studio {

namespace fs = std::filesystem;

std::string not_started_text(const run::LoadedMission& loaded, const run::Error& error) {
  using run::ErrorKind;
  std::string first;  // the first error in the mission text, placed
  std::size_t errors = 0;
  for (const core::Diagnostic& d : loaded.diagnostics) {
    if (d.severity != core::Severity::Error) continue;
    if (errors++ == 0) {
      first = d.message;
      if (d.span.file < loaded.sources.size()) {
        const std::string file = fs::path(loaded.sources.path(d.span.file)).filename().string();
        const core::LineCol at = loaded.sources.line_col(d.span.file, d.span.offset);
        switch (d.precision) {
          case core::Precision::Span: first = fmt::format("{}:{}:{}: {}", file, at.line, at.col, d.message); break;
          case core::Precision::Line: first = fmt::format("{}:{}: {}", file, at.line, d.message); break;
          case core::Precision::File: first = fmt::format("{}: {}", file, d.message); break;
        }
      }
    }
  }
  const std::string more =
      errors > 1 ? fmt::format(" (and {} more error{})", errors - 1, errors == 2 ? "" : "s") : std::string();
  std::string what = error.input.empty() ? error.message : error.input + ": " + error.message;
  switch (error.kind) {
    case ErrorKind::Invalid:
      if (errors > 0) return fmt::format("the mission does not load: {}{}", first, more);
      return "an input is invalid: " + what;
    case ErrorKind::Unreadable: return "an input cannot be read: " + what;
    case ErrorKind::FailsVerification:
      return "the mission fails verification (the Verify panel shows which property and a witness)";
    case ErrorKind::Usage: return "the run's settings do not go together: " + what;
    case ErrorKind::LogUnwritable: return "the run's log cannot be written: " + what;
    case ErrorKind::VehicleUnavailable: return "the vehicle cannot be reached: " + what;
  }
  return what;
}

std::string run_log_name(const std::string& mission, std::chrono::system_clock::time_point utc, int n) {
  const std::string dir = fs::path(mission).parent_path().generic_string();
  return fmt::format("{}runs/{}", dir.empty() ? "" : dir + "/", tactical::dated_log_name(mission, utc, n));
}

namespace {

// The log file, created inside the folder through the sandbox, as a stream.
struct StudioLog {
  std::string relative;
  std::unique_ptr<__gnu_cxx::stdio_filebuf<char>> buf;
  std::unique_ptr<std::ostream> out;
};

core::Result<StudioLog> create_log(const Sandbox& sandbox, const std::string& mission) {
  const auto now = std::chrono::system_clock::now();
  const std::string first = run_log_name(mission, now);
  const std::string folder = fs::path(first).parent_path().generic_string();
  for (int n = 1; n <= 20; ++n) {
    const std::string name = fs::path(run_log_name(mission, now, n)).filename().string();
    auto fd = sandbox.create_new(folder, name);
    if (!fd && fd.error().code == core::ErrorCode::Overflow) continue;  // taken: the next name
    if (!fd) return fd.error();
    StudioLog log;
    log.relative = fmt::format("{}/{}", folder, name);
    log.buf = std::make_unique<__gnu_cxx::stdio_filebuf<char>>(fd.value(), std::ios::out | std::ios::binary);
    log.out = std::make_unique<std::ostream>(log.buf.get());
    return log;
  }
  return core::Error{core::ErrorCode::Io, fmt::format("{}: 20 logs started this second; not another", first)};
}

}  // namespace

StudioRunner::~StudioRunner() {
  std::thread running;
  {
    // A run going ends through its safe end, waited for here; when a stop
    // was asked already, asking again would cut that safe end short.
    std::lock_guard lock(mutex_);
    if (session_ && !stop_asked_) session_->stop("studio", "the studio is closing", 1, run::StopMode::Abort);
    running = std::move(thread_);
  }
  // Joined without the lock: the run takes it as it ends.
  if (running.joinable()) running.join();
  // A PROLOG run on the PrologThread: wait for its end (it was stopped).
  while (running_) std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

core::Result<void> StudioRunner::start(const RunRequest& request) {
  const core::MissionLanguage language = core::mission_language(request.mission.string());
  if (language == core::MissionLanguage::None) {
    return core::Error{core::ErrorCode::InvalidInput, "the studio runs CORAL (.coral) and PROLOG (.pl) missions"};
  }
  std::lock_guard lock(mutex_);
  if (running_) return core::Error{core::ErrorCode::Overflow, "a run is going; stop it first"};
  if (thread_.joinable()) thread_.join();
  running_ = true;
  auto job = [this, request] {
    run::RunOptions o;
    o.sonar_dir = sonar_dir_;
    // Every input the run reads itself goes through the sandbox: a file
    // swapped for a link after the server checked it is still refused.
    o.read_file = [this](const std::string& path) { return sandbox_.read_path(path); };
    run_impl(request, o, {}, {}, /*studio_log=*/true);
    running_ = false;
  };
  if (language == core::MissionLanguage::Prolog) {
    // SWI-Prolog lives on one thread of the process.
    if (!PrologThread::instance().post(job)) {
      running_ = false;
      return core::Error{core::ErrorCode::Overflow,
                         "the PROLOG engine is busy checking rules (try again), or SWI-Prolog was started on another "
                         "thread of this process"};
    }
    return core::Result<void>();
  }
  thread_ = std::thread(job);
  return core::Result<void>();
}

void StudioRunner::stop(const std::string& who, const std::string& reason, int exit_code, run::StopMode mode) {
  std::lock_guard lock(mutex_);
  if (!session_) return;
  stop_asked_ = true;
  session_->stop(who, reason, exit_code, mode);
}

run::RunReport StudioRunner::run_here(const RunRequest& request, run::RunOptions o,
                                      const std::vector<run::RunObserver*>& observers, const OnLoaded& on_loaded) {
  return run_impl(request, std::move(o), observers, on_loaded, /*studio_log=*/false);
}

run::RunReport StudioRunner::run_impl(const RunRequest& request, run::RunOptions o,
                                      const std::vector<run::RunObserver*>& observers, const OnLoaded& on_loaded,
                                      bool studio_log) {
  RunPublisher publisher(hub_);
  const std::uint64_t run = ++runs_;
  const bool prolog = core::mission_language(request.mission.string()) == core::MissionLanguage::Prolog;
  nlohmann::json nets = nlohmann::json::array();
  if (!prolog) nets = compile_mission(sandbox_, request.relative, std::nullopt, catalogue_).model["nets"];
  // The mission log: in runs/ beside the mission, created inside the folder.
  std::optional<StudioLog> log;
  std::string log_problem;
  if (studio_log && o.log.empty() && !o.log_stream) {
    auto created = create_log(sandbox_, request.relative);
    if (created) {
      log = std::move(created).value();
      o.log = log->relative;
      o.log_stream = log->out.get();
      publisher.set_log(log->relative);
    } else {
      log_problem = created.error().message;
    }
  }
  hub_.publish("run_start", {{"run", run},
                             {"mission", request.relative},
                             {"kind", prolog ? "prolog" : "coral"},
                             {"scenario", request.scenario.empty() ? "nominal" : request.scenario},
                             {"speed", request.speed},
                             {"log", log ? log->relative : ""},
                             {"nets", nets}});
  if (!log_problem.empty()) {
    hub_.publish("report", {{"t", 0.0}, {"text", "no mission log for this run: " + log_problem}});
  }
  o.mission = request.mission.string();
  // From the page: the file the server checked inside the root, never the
  // name as a path.
  o.scenario = request.scenario_file.empty() ? request.scenario : request.scenario_file.string();
  if (o.vehicle.empty()) {
    o.realtime = true;  // watching live is on the wall clock
    o.speed = request.speed;
  }
  run::RunSession session(o);
  for (run::RunObserver* obs : observers) session.add_observer(*obs);
  session.add_observer(publisher);
  {
    std::lock_guard lock(mutex_);
    session_ = &session;
    stop_asked_ = false;
  }
  // Problems before the mission starts (it fails verification, say) reach
  // the page as the run's end, in the studio's words.
  (void)session.load();
  if (on_loaded) on_loaded(session.loaded());
  run::RunReport report = session.run();
  {
    std::lock_guard lock(mutex_);
    session_ = nullptr;
  }
  if (log) {
    log->out->flush();
    // A run that never started wrote nothing: no empty log is left behind.
    if (!report.result) {
      const fs::path rel(log->relative);
      (void)sandbox_.remove_empty(rel.parent_path().generic_string(), rel.filename().string());
      log->relative.clear();
    }
  }
  if (!report.result) {
    hub_.publish("run_end", {{"outcome", "failed"},
                             {"exit", ""},
                             {"reason", report.error ? not_started_text(session.loaded(), *report.error)
                                                     : std::string("the run did not start")},
                             {"error", report.error ? std::string(run::to_string(report.error->kind)) : "internal"},
                             {"phase", ""},
                             {"stopped_by", ""},
                             {"stop", ""},
                             {"final_depth_m", nullptr},
                             {"surfaced", false},
                             {"log", log ? log->relative : ""},
                             {"t", 0.0}});
  }
  return report;
}

}  // namespace strata::studio
