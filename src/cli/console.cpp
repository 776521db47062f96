#include "cli/console.h"

#include <algorithm>

#include <fmt/format.h>

namespace strata::cli {

bool Console::shown(const std::string& text, std::optional<double> sim_time_s) {
  if (!sim_time_s) return true;
  if (!instant_s_ || *sim_time_s > *instant_s_ + 1e-9) {
    say_hidden();
    instant_s_ = sim_time_s;
    at_instant_.clear();
  }
  constexpr std::size_t kMaxTexts = 1000;  // distinct lines remembered at one instant
  if (at_instant_.size() >= kMaxTexts && !at_instant_.contains(text)) return true;
  const std::size_t n = ++at_instant_[text];
  if (n <= kRepeatsShown) return true;
  if (hidden_++ == 0) {
    out_ << fmt::format("[{:7.1f} s] (lines repeating at this instant: the rest are counted, not shown)\n",
                        *sim_time_s);
  }
  return false;
}

void Console::say_hidden() {
  if (hidden_ == 0 || !instant_s_) return;
  if (status_shown_) out_ << "\r\033[K";
  out_ << fmt::format("[{:7.1f} s] {} repeated lines not shown\n", *instant_s_, hidden_);
  status_shown_ = false;
  hidden_ = 0;
}

void Console::print(const std::string& text, std::optional<double> sim_time_s) {
  if (!shown(text, sim_time_s)) return;
  if (status_shown_) out_ << "\r\033[K";
  if (sim_time_s) {
    out_ << fmt::format("[{:7.1f} s] {}\n", *sim_time_s, text);
  } else {
    out_ << text << "\n";
  }
  status_shown_ = false;
  if (tty_) draw_status(true);
  out_.flush();
}

void Console::draw_status(bool force) {
  if (!tty_) return;
  if (!force && sim_time_s_ - last_draw_s_ < 0.1) return;
  last_draw_s_ = sim_time_s_;
  std::string phase = current_phase_.empty() ? "-" : current_phase_;
  std::string depth = depth_m_ ? fmt::format("{:.2f} m", *depth_m_) : "-";
  std::string setpoint = setpoint_m_ ? fmt::format("{:.2f} m", *setpoint_m_) : "-";
  std::string text = fmt::format("{:7.1f} s | {} | depth {} | setpoint {} | {}", sim_time_s_, phase, depth, setpoint,
                                 action_.empty() ? "idle" : action_);
  out_ << "\r\033[K" << text;
  out_.flush();
  status_shown_ = true;
}

void Console::phase_started(const strategic::PhaseStart& e) {
  sim_time_s_ = std::max(sim_time_s_, e.sim_time_s);
  live_[e.instance] = Live{std::string(e.name), e.depth};
  current_phase_ = std::string(e.name);
  if (e.depth == 0) {
    print(fmt::format("mission {} started", e.name), e.sim_time_s);
    return;
  }
  print(fmt::format("{}phase {} started", std::string(2 * (e.depth - 1), ' '), e.name), e.sim_time_s);
}

void Console::phase_ended(const strategic::PhaseEnd& e) {
  sim_time_s_ = std::max(sim_time_s_, e.sim_time_s);
  auto it = live_.find(e.instance);
  std::size_t depth = it != live_.end() ? it->second.depth : 0;
  if (it != live_.end()) live_.erase(it);
  // The status line shows the deepest phase still running.
  current_phase_.clear();
  std::size_t deepest = 0;
  for (const auto& [id, live] : live_) {
    if (current_phase_.empty() || live.depth >= deepest) {
      current_phase_ = live.name;
      deepest = live.depth;
    }
  }
  if (depth == 0) return;  // the mission itself: the summary says how it ended
  std::string result = e.cancelled ? "cancelled" : e.exit_index == 0 ? "completed" : "aborted";
  print(fmt::format("{}phase {} {}{}", std::string(2 * (depth - 1), ' '), e.name, result,
                    e.cancelled ? "" : fmt::format(" (exit {})", e.exit)),
        e.sim_time_s);
}

namespace {

// " 1.5 \"text\"": each argument as the wire writes it, strings quoted.
std::string call_arguments(std::span<const tactical::Value> args) {
  std::string out;
  for (const auto& a : args) {
    out += a.type == tactical::Value::Type::String ? fmt::format(" \"{}\"", a.text) : " " + tactical::to_string(a);
  }
  return out;
}

}  // namespace

void Console::action_started(const strategic::ActionStart& e) {
  if (e.is_phase() || e.is_call(core::CallVerb::Report)) return;
  sim_time_s_ = std::max(sim_time_s_, e.sim_time_s);
  action_ = fmt::format("{} {}", e.kind_name(), e.primitive);
  // -v: the call as sent, arguments included ("exec set_speed 1.5").
  if (calls_) calls_in_flight_[e.id] = action_ + call_arguments(e.args);
  draw_status(false);
}

void Console::action_finished(const strategic::ActionFinish& e) {
  sim_time_s_ = std::max(sim_time_s_, e.sim_time_s);
  action_.clear();
  if (auto it = calls_in_flight_.find(e.id); calls_ && it != calls_in_flight_.end()) {
    print(fmt::format("  {} -> {}", it->second, e.value ? 1 : 0), e.sim_time_s);
    calls_in_flight_.erase(it);
  }
}

void Console::notice(const strategic::Notice& e) { print("note: " + e.text, e.sim_time_s); }

void Console::guard_tripped(const strategic::GuardTrip& e) {
  std::string what;
  for (const auto& p : e.preempted_phases) what += (what.empty() ? "" : ", ") + p;
  print(fmt::format("guard {} of {} tripped ({}){}", e.guard, e.net, e.condition,
                    what.empty() ? std::string() : ": pre-empted " + what),
        e.sim_time_s);
}

void Console::mission_ended(const strategic::MissionResult&) { action_.clear(); }

void Console::report(const std::string& text, double sim_time_s) {
  sim_time_s_ = std::max(sim_time_s_, sim_time_s);
  print("REPORT: " + text, sim_time_s);
}

void Console::telemetry(const protocol::Telemetry& t) {
  sim_time_s_ = std::max(sim_time_s_, t.sim_time_s);
  depth_m_ = t.filtered_depth_m ? t.filtered_depth_m : t.depth_m;
  if (t.setpoint_m) setpoint_m_ = t.setpoint_m;
  draw_status(false);
}

void Console::vehicle_event(const std::string& text, double sim_time_s) {
  sim_time_s_ = std::max(sim_time_s_, sim_time_s);
  print("vehicle: " + text, sim_time_s);
}

void Console::note(const std::string& text, std::optional<double> sim_time_s) { print(text, sim_time_s); }

void Console::clear_status() {
  say_hidden();
  if (status_shown_) {
    out_ << "\r\033[K";
    out_.flush();
    status_shown_ = false;
  }
  tty_ = false;
}

}  // namespace strata::cli
