#pragma once
// Inside run::RunSession (not for other components): the objects of one
// run and its stages, split over session.cpp (driving and the safe end) and
// session_start.cpp (the stages before the mission starts).
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <asio.hpp>
#include <fmt/format.h>

#include "run/loaded_mission.h"
#include "run/safe_end.h"
#include "run/scripted_tactics.h"
#include "run/session.h"
#include "run/sonar_child.h"
#include "strategic/log_observer.h"
#include "strategic/tactics.h"
#include "tactical/mission_log.h"
#include "tactical/tactical_level.h"
#include "tactical/execution_link.h"
#include "tactical/imc_link.h"
#include "tactical/vehicle_link.h"
#include "vehicle/server.h"

namespace strata::run {
namespace detail {

// Lockstep: wall seconds allowed per simulated second of a call (>= 100x real time).
constexpr double kLockstepWallPerSim = 0.01;
constexpr const char* kShutdown = "shutdown_network";

// The most entries the summary's phases list keeps; the rest are counted.
constexpr std::size_t kMaxPhaseEntries = 100;

// Records the depth-1 phases as they end, for the summary. Bounded: the same
// ending again is one entry with its count ("2 aborted (x624999)"), and past
// kMaxPhaseEntries the last entry counts the rest ("... and 12 more").
class PhaseRecorder final : public strategic::Observer {
 public:
  explicit PhaseRecorder(std::vector<std::string>& phases) : phases_(phases) {}
  void phase_started(const strategic::PhaseStart& e) override { depth_[e.instance] = e.depth; }
  void phase_ended(const strategic::PhaseEnd& e) override {
    auto it = depth_.find(e.instance);
    if (it == depth_.end()) return;
    if (it->second == 1) {
      add(fmt::format("{} {}", e.name, e.cancelled ? "cancelled" : e.exit_index == 0 ? "completed" : "aborted"));
    }
    depth_.erase(it);
  }

 private:
  void add(std::string entry) {
    if (!phases_.empty() && entry == last_) {
      phases_.back() = fmt::format("{} (x{})", last_, ++repeats_);
      return;
    }
    last_ = entry;
    repeats_ = 1;
    if (more_ == 0 && phases_.size() + 1 < kMaxPhaseEntries) {
      phases_.push_back(std::move(entry));
      return;
    }
    if (more_++ == 0) phases_.emplace_back();
    phases_.back() = fmt::format("... and {} more", more_);
    last_.clear();
  }

  std::vector<std::string>& phases_;
  std::map<strategic::InstanceId, std::size_t> depth_;
  std::string last_;  // the newest entry, before its count
  std::size_t repeats_ = 0;
  std::size_t more_ = 0;
};

inline bool link_error(const strategic::MissionResult& r) {
  return r.call_error &&
         (*r.call_error == tactical::CallError::Kind::TimedOut || *r.call_error == tactical::CallError::Kind::LinkLost);
}

}  // namespace detail

// The objects of one run, alive inside RunSession::run(). Each stage is a
// member function; those before the mission return why the run cannot start.
using Stage = core::Result<void, Error>;

class RunSession::Run {
 public:
  explicit Run(RunSession& session)
      : session_(session),
        o_(session.options_),
        wall_start_(session.load_started_.value_or(std::chrono::steady_clock::now())),
        loaded_(*session.loaded_) {}

  RunReport execute();

  // On the loop: a stop request arrived (RunSession::stop()).
  void on_stop();
  // Any thread, under the session's mutex: wake an executor that holds the loop.
  void interrupt(const std::string& reason) {
    if (executor_) executor_->interrupt(reason);
  }
  asio::io_context& io() { return io_; }

 private:
  // Mission, catalogue, parameters, scenario, data: loaded and checked.
  Stage load_inputs();
  // The mission log created, with its header and the verification.
  Stage open_log();
  // The embedded vehicle started on one end of a pair of local sockets, or
  // --vehicle parsed.
  Stage open_vehicle();
  // The link connected and hello answered; the vehicle's clock known.
  Stage connect();
  // The same for an IMC vehicle (--vehicle imc://HOST:PORT[/ID]).
  Stage connect_imc();
  std::string embedded_world() const;  // the header's world and scenario, and where it came from
  // The Sonar Manager started and connected, when a folder is given.
  Stage start_sonar();
  // The Tactical level, the executor and their observers, wired.
  void build_levels();
  // The loop run until the mission and its safe end are over.
  void drive();
  // The executor's end: on to the safe end, or straight to wrap_up().
  void mission_ended(const strategic::MissionResult& result);
  // Whether the vehicle still needs surfacing and `done` from the run.
  bool needs_safe_end(const strategic::MissionResult& result) const;
  // The link closed and the embedded vehicle settled: the loop may end.
  void wrap_up();
  // The Sonar Manager waited for (or stopped) and summarised.
  void close_sonar();
  // Times, the final vehicle state and the exit code into the report.
  void finish_report();
  // vehicle_final and mission_end written, the log closed.
  void write_end_of_log();
  // A stop decided on the loop itself (a limit), as RunSession::stop().
  void stop_here(const std::string& who, const std::string& reason, int exit_code);
  // The simulated-time limit checked (lockstep only).
  void check_limits();
  void note(const std::string& text, std::optional<double> t = std::nullopt) {
    for (RunObserver* o : session_.observers_) o->note(text, t);
  }

  RunSession& session_;
  const RunOptions& o_;
  std::chrono::steady_clock::time_point wall_start_;
  RunReport report_;

  LoadedMission& loaded_;  // the session's
  std::optional<tactical::MissionLog> log_;
  asio::io_context io_;
  std::vector<std::string> vehicle_log_;
  std::optional<vehicle::Simulation> sim_;
  std::unique_ptr<vehicle::VehicleServer> server_;
  // The link's end of the pair the embedded vehicle holds the other of,
  // from open_vehicle() to connect().
  std::optional<protocol::LineConnection::Socket> paired_;
  tactical::LinkOptions link_options_;
  std::optional<std::uint16_t> sonar_port_;  // as hello announced it
  std::shared_ptr<tactical::ExecutionLink> link_;
  std::shared_ptr<tactical::ImcLink> imc_;  // the same link, when the vehicle is an IMC one
  std::optional<SonarChild> sonar_;
  std::optional<tactical::TacticalLevel> tactical_;
  std::optional<strategic::TacticalTactics> tactics_;
  std::unique_ptr<ScriptedTactics> scripted_;  // --answers: in front of tactics_
  std::unique_ptr<strategic::Executor> executor_;
  std::optional<strategic::LogObserver> log_observer_;
  std::optional<detail::PhaseRecorder> phase_recorder_;
  std::optional<SafeEnd> safe_end_;
  bool mission_sent_done_ = false;
  bool safe_end_running_ = false;
  bool settling_ = false;  // waiting for the embedded vehicle to surface by itself (wrap_up)
  bool finished_ = false;
  std::optional<std::string> internal_error_;
};

}  // namespace strata::run
