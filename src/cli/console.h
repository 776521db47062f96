#pragma once
// The operator's console during `strata run`: an observer of the run (the
// Strategic level's events, the Tactical level's reports, telemetry and
// vehicle events, the run's own notes).
// Event lines ("[  12.3 s] phase dive_from_surface completed") always; on a
// TTY also a live status line (phase, depth, setpoint, sim time, the action
// in flight), redrawn in place at most once per 0.1 s of simulated time so a
// lockstep run does not flood the terminal. A line repeated at one
// simulated instant (a loop that never waits) is shown kRepeatsShown times,
// then counted: "N lines repeated at 0.2 s not shown".
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "protocol/message.h"
#include "run/observer.h"

namespace strata::cli {

class Console final : public run::RunObserver {
 public:
  // calls: also a line for each primitive call and its answer (-v).
  Console(std::ostream& out, bool tty, bool calls = false) : out_(out), tty_(tty), calls_(calls) {}

  void phase_started(const strategic::PhaseStart& e) override;
  void phase_ended(const strategic::PhaseEnd& e) override;
  void action_started(const strategic::ActionStart& e) override;
  void action_finished(const strategic::ActionFinish& e) override;
  void notice(const strategic::Notice& e) override;
  void guard_tripped(const strategic::GuardTrip& e) override;
  void mission_ended(const strategic::MissionResult& e) override;

  void report(const std::string& text, double sim_time_s) override;
  void telemetry(const protocol::Telemetry& t) override;
  void vehicle_event(const std::string& text, double sim_time_s) override;
  // Any other event line ("vehicle: 6.1 s: watchdog ...").
  void note(const std::string& text, std::optional<double> sim_time_s) override;
  // Erases the status line (before the summary).
  void run_ended(const run::RunReport&) override { clear_status(); }
  void clear_status();

 private:
  void print(const std::string& text, std::optional<double> sim_time_s);
  // Whether an event line is shown: the same text more than
  // kRepeatsShown times at one simulated instant (a phase restarted in a
  // loop that never waits) is counted instead, and said once.
  bool shown(const std::string& text, std::optional<double> sim_time_s);
  void say_hidden();
  void draw_status(bool force);

  std::ostream& out_;
  bool tty_;
  bool calls_;
  std::map<strategic::ActionId, std::string> calls_in_flight_;  // with calls_: "exec submerge" by action
  bool status_shown_ = false;
  double last_draw_s_ = -1.0;
  double sim_time_s_ = 0.0;
  struct Live {
    std::string name;
    std::size_t depth;
  };
  std::map<strategic::InstanceId, Live> live_;  // running nets by instance
  std::string current_phase_;                   // the one last started, for the status line
  std::optional<double> depth_m_;
  std::optional<double> setpoint_m_;
  std::string action_;
  // Lines at the current instant, by text (cleared when time moves; at most
  // kMaxTexts kept), and those not shown.
  std::optional<double> instant_s_;
  std::map<std::string, std::size_t> at_instant_;
  std::size_t hidden_ = 0;
};

// The same event line shown at most this often at one simulated instant.
inline constexpr std::size_t kRepeatsShown = 3;

}  // namespace strata::cli
