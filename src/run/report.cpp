#include "run/report.h"

#include <fmt/format.h>

namespace strata::run {
namespace {

using strategic::Outcome;

std::string format_wall(double seconds) {
  return seconds < 1.0 ? fmt::format("{:.0f} ms", seconds * 1000.0) : fmt::format("{:.2f} s", seconds);
}

}  // namespace

std::string ending_text(const RunReport& r) {
  if (!r.result) return "did not start";
  if (r.result->outcome == Outcome::Completed) return "completed";
  if (r.result->outcome == Outcome::Aborted) return "ABORTED";
  if (r.stopped_by == "limit") return "ABORTED: a limit was reached";
  if (r.stopped_by == "studio") return "ABORTED: stopped from the studio";
  if (!r.stopped_by.empty()) return fmt::format("ABORTED: interrupted by {}", r.stopped_by);
  if (r.link_lost) return "ABORTED: lost the link to the vehicle";
  return "ABORTED: the Strategic level could not go on";
}

std::string summary_text(const RunReport& r) {
  if (!r.result) return "";
  std::string out;
  auto line = [&out](const std::string& text) { out += text + "\n"; };
  line(fmt::format("mission {}: {}{}", r.mission_name, ending_text(r),
                   r.result->exit.empty() ? "" : fmt::format(" (exit {})", r.result->exit)));
  if (!r.result->reason.empty()) line("  reason: " + r.result->reason);
  if (r.result->outcome != Outcome::Completed && !r.vehicle_reason.empty()) {
    line("  the vehicle said: " + r.vehicle_reason);
  }
  std::string phases;
  for (const auto& p : r.phases) phases += (phases.empty() ? "" : ", ") + p;
  line("  phases: " + (phases.empty() ? std::string("none ended") : phases));
  const double speedup = r.wall_time_s > 0 ? r.sim_time_s / r.wall_time_s : 0.0;
  line(fmt::format("  sim time {:.1f} s, {} primitive calls, wall time {}{}", r.sim_time_s, r.primitive_calls,
                   format_wall(r.wall_time_s),
                   r.lockstep && r.result->outcome != Outcome::Failed && speedup > 1.0
                       ? fmt::format(" ({:.0f}x real time)", speedup)
                       : ""));
  if (r.final_depth_m) {
    line(fmt::format("  vehicle: depth {:.2f} m at {:.1f} s{}", *r.final_depth_m, r.final_time_s.value_or(0.0),
                     r.vehicle_watchdog_tripped ? ", surfaced by its own watchdog" : ""));
  } else if (r.last_telemetry) {
    const protocol::Telemetry& t = *r.last_telemetry;
    std::string depth = t.depth_m ? fmt::format("depth {:.2f} m", *t.depth_m) : std::string("no depth");
    line(fmt::format("  vehicle: {}{} at {:.1f} s (its last telemetry)", depth,
                     t.heading_deg ? fmt::format(", heading {:.0f} deg", *t.heading_deg) : "", t.sim_time_s));
  } else {
    line("  vehicle: no telemetry heard");
  }
  if (r.link_lost && !r.link_lost_why.empty()) line("  link: lost (" + r.link_lost_why + ")");
  if (!r.sonar_summary.empty()) line("  sonar: " + r.sonar_summary);
  if (r.emergency_surface) {
    line(fmt::format("  after it: exec surface sent by strata run; {}",
                     r.emergency_surfaced ? "the vehicle reached the surface" : "not confirmed at the surface"));
  }
  if (r.emergency_shutdown) {
    line(fmt::format("  after it: ood shutdown_network sent by strata run{}",
                     r.shutdown_error.empty() ? "" : ", unanswered (" + r.shutdown_error + ")"));
  }
  if (r.hurried) line("  after it: cut short by a second stop request");
  if (!r.log_path.empty()) line(fmt::format("  log: {} ({} lines)", r.log_path, r.log_lines));
  return out;
}

}  // namespace strata::run
