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
  // The mission log's outcome word first ("aborted": the mission took its
  // abort exit; "failed": something else ended it), then why.
  if (r.result->outcome == Outcome::Aborted) return "aborted";
  if (r.stopped_by == "limit") return "failed: a limit was reached";
  if (r.stopped_by == "studio") return "failed: stopped from the studio";
  if (!r.stopped_by.empty()) return fmt::format("failed: interrupted by {}", r.stopped_by);
  if (r.link_lost) return "failed: lost the link to the vehicle";
  if (!r.vehicle_fault.empty()) return "failed: the vehicle stopped taking this run's commands";
  return "failed: the Strategic level could not go on";
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
  for (const auto& p : r.phases) phases += (phases.empty() ? "" : ", ") + p;  // bounded (PhaseRecorder)
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
  if (!r.vehicle_fault.empty()) line("  vehicle fault: " + r.vehicle_fault);
  if (!r.imc_dropped.empty()) line("  imc: " + r.imc_dropped);
  if (!r.sonar_summary.empty()) line("  sonar: " + r.sonar_summary);
  if (r.emergency_surface) {
    line(fmt::format("  after it: exec surface sent by strata run{}; {}",
                     r.surface_method == "abort"       ? " (as an IMC Abort: the vehicle took no Reference)"
                     : r.surface_method == "reference" ? " (as an IMC Reference, z = 0)"
                                                       : "",
                     r.emergency_surfaced ? "the vehicle reached the surface" : "not confirmed at the surface"));
  }
  if (r.emergency_shutdown) {
    line(fmt::format("  after it: ood shutdown_network sent by strata run{}",
                     r.shutdown_error.empty() ? "" : ", unanswered (" + r.shutdown_error + ")"));
  }
  if (r.hurried) line("  after it: cut short by a second stop request");
  if (!r.log_path.empty()) {
    line(fmt::format("  log: {} ({} lines{})", r.log_path, r.log_lines,
                     r.log_dropped ? fmt::format(", {} more past its limit not written", r.log_dropped) : ""));
  }
  return out;
}

nlohmann::json summary_json(const RunReport& r) {
  using nlohmann::json;
  json j{{"started", r.result.has_value()}, {"exit_code", r.exit_code}, {"mission", r.mission_name}};
  if (!r.result) {
    if (r.error) {
      j["error"] = {{"kind", std::string(to_string(r.error->kind))},
                    {"input", r.error->input.empty() ? json(nullptr) : json(r.error->input)},
                    {"message", r.error->message}};
      if (r.error->place) {
        j["error"]["place"] = {
            {"file", r.error->place->file}, {"line", r.error->place->line}, {"column", r.error->place->column}};
      }
    }
    return j;
  }
  auto optional = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
  j["outcome"] = std::string(strategic::to_string(r.result->outcome));
  j["ending"] = ending_text(r);
  j["exit"] = r.result->exit.empty() ? json(nullptr) : json(r.result->exit);
  j["reason"] = r.result->reason;
  j["stopped_by"] = r.stopped_by.empty() ? json(nullptr) : json(r.stopped_by);
  j["stop_mode"] = r.stop_mode.empty() ? json(nullptr) : json(r.stop_mode);
  j["link_lost"] = r.link_lost ? json(r.link_lost_why) : json(nullptr);
  j["vehicle_reason"] = r.vehicle_reason.empty() ? json(nullptr) : json(r.vehicle_reason);
  j["phases"] = r.phases;
  j["primitive_calls"] = r.primitive_calls;
  j["sim_time_s"] = r.sim_time_s;
  j["wall_time_s"] = r.wall_time_s;
  j["clock"] = r.lockstep ? "lockstep" : "wall";
  json vehicle{{"depth_m", optional(r.final_depth_m)},
               {"time_s", optional(r.final_time_s)},
               {"watchdog_tripped", r.vehicle_watchdog_tripped},
               {"from", r.final_depth_m    ? "embedded"
                        : r.last_telemetry ? "last_telemetry"
                                           : "none"}};
  if (!r.final_depth_m && r.last_telemetry) {
    vehicle["depth_m"] = optional(r.last_telemetry->depth_m);
    vehicle["time_s"] = r.last_telemetry->sim_time_s;
  }
  j["vehicle"] = vehicle;
  j["safe_end"] = {{"surface_sent", r.emergency_surface},
                   {"surfaced", r.emergency_surfaced},
                   {"shutdown_sent", r.emergency_shutdown},
                   {"shutdown_error", r.shutdown_error.empty() ? json(nullptr) : json(r.shutdown_error)},
                   {"hurried", r.hurried}};
  j["sonar"] = r.sonar_exit || !r.sonar_summary.empty()
                   ? json{{"exit", r.sonar_exit ? json(*r.sonar_exit) : json(nullptr)}, {"summary", r.sonar_summary}}
                   : json(nullptr);
  j["log"] = r.log_path.empty() ? json(nullptr) : json{{"path", r.log_path}, {"lines", r.log_lines}};
  return j;
}

}  // namespace strata::run
