#include "vehicle/execution.h"

#include <cmath>

#include <fmt/format.h>

namespace strata::vehicle {

using protocol::Verb;

const std::vector<FunctionSpec>& function_table() {
  static const std::vector<FunctionSpec> table = {
      {Verb::Exec,
       "setpoint",
       {{"depth", "m"}, {"timeout", "s"}},
       "load the next depth setpoint and its time limit (sent by next_setpt_data)"},
      {Verb::Exec, "start_depth_filter", {}, "start the depth filter (depth and depth rate)"},
      {Verb::Exec, "submerge", {}, "engage the depth law toward the loaded setpoint"},
      {Verb::Exec, "start_timer", {}, "start the mission timer with the loaded setpoint's timeout"},
      {Verb::Exec, "set_timer", {{"seconds", "s"}}, "start the mission timer with this limit (> 0)"},
      {Verb::Exec, "sleep", {{"duration", "s"}}, "let the given time pass, then reply"},
      {Verb::Exec, "surface", {}, "drive to the surface"},
      {Verb::Exec,
       "heading",
       {{"heading", "deg"}},
       "engage the heading law toward a compass heading (0 to 360), the short way round"},
      {Verb::Exec, "start_sonar", {}, "start the scanning sonar (pings to the sonar socket)"},
      {Verb::Exec, "stop_sonar", {}, "stop the scanning sonar"},
      {Verb::Exec,
       "goto_depth",
       {{"depth", "m"}},
       "start the depth filter if off and engage the depth law toward a depth, with no time limit"},
      {Verb::Exec,
       "set_speed",
       {{"speed", "m/s"}},
       "the cruise speed of the guidance (0 to the top speed): a guidance running takes it at once; no motion by "
       "itself"},
      {Verb::Exec,
       "set_sway",
       {{"speed", "m/s"}},
       "hold a sideways speed through the water (+ starboard, - port) with the transverse thrusters"},
      {Verb::Exec,
       "goto_xy",
       {{"x", "m"}, {"y", "m"}},
       "line-of-sight guidance to a waypoint (x east, y north) at the cruise speed; there, hold the point"},
      {Verb::Exec,
       "track",
       {{"x0", "m"}, {"y0", "m"}, {"x1", "m"}, {"y1", "m"}},
       "line-of-sight guidance along the line from (x0, y0) to (x1, y1); at its end, hold the point"},
      {Verb::Exec,
       "loiter",
       {{"x", "m"}, {"y", "m"}, {"radius", "m"}},
       "circle (x, y) clockwise at the radius (>= 5 m) and the cruise speed until another guidance command"},
      {Verb::Exec, "hold_position", {}, "station keeping: hold the estimated position of now"},
      {Verb::Exec,
       "start_rows",
       {{"x", "m"}, {"y", "m"}, {"heading", "deg"}, {"length", "m"}, {"spacing", "m"}, {"count", ""}},
       "record a lawnmower pattern (row i starts i * spacing to starboard of the first, odd rows run back); "
       "no motion"},
      {Verb::Exec, "next_row", {}, "track along the next row of the pattern (err failed when none is left)"},
      {Verb::Exec,
       "stop",
       {},
       "stop the propulsion motors, the sway and the guidance; hold the heading; the cruise speed is kept"},
      {Verb::Exec, "gps_fix", {}, "take a GPS fix now (only at the surface, in open water); resets the estimate"},
      {Verb::Exec, "set_altitude_floor", {{"floor", "m"}}, "the altitude below which altitude_low is true"},
      {Verb::Ask, "depth_filter_off", {}, "is the depth filter off?"},
      {Verb::Ask, "depth_reached", {}, "is the vehicle settled at the setpoint?"},
      {Verb::Ask, "time_out", {}, "has the mission timer run out?"},
      {Verb::Ask, "system_problem", {}, "has the vehicle detected a fault (a leak, a depth-cell dropout; latched)?"},
      {Verb::Ask, "surface_reached", {}, "is the vehicle at the surface?"},
      {Verb::Ask, "heading_reached", {}, "is the vehicle settled on the commanded heading?"},
      {Verb::Ask, "target_detected", {}, "does the sonar's last sweep show an object short of the walls?"},
      {Verb::Ask, "waypoint_reached", {}, "has the guidance reached its waypoint or the end of its track line?"},
      {Verb::Ask, "altitude_low", {}, "is the altitude below the floor (or the altimeter dead under water)?"},
      {Verb::Ask, "position_uncertain", {}, "is the position estimate's 1-sigma above the limit?"},
      {Verb::Ask, "gps_available", {}, "can a GPS fix be taken now (open water, antenna dry, receiver working)?"},
      {Verb::Ask, "rows_done", {}, "has every row of the pattern been started (false with no pattern)?"},
      {Verb::Ood, "start_network", {}, "open the vehicle network; commands are refused before"},
      {Verb::Ood, "shutdown_network", {}, "stop the thrusters and close the vehicle network"},
  };
  return table;
}

const FunctionSpec* find_function(Verb verb, std::string_view name) {
  for (const auto& f : function_table()) {
    if (f.verb == verb && f.name == name) return &f;
  }
  return nullptr;
}

namespace {

Outcome refuse(protocol::ErrorCode code, std::string message) {
  Outcome o;
  o.refused = code;
  o.message = std::move(message);
  return o;
}

Outcome from(const core::Result<void>& r) {
  Outcome o;
  o.value = r.ok();
  if (!r) o.message = r.error().message;
  return o;
}

Outcome answer(bool v) {
  Outcome o;
  o.value = v;
  return o;
}

}  // namespace

Outcome execute(Simulation& sim, const protocol::Request& request) {
  const FunctionSpec* spec = find_function(request.verb, request.name);
  if (!spec) {
    // Say so when the name exists under another verb: a common slip.
    for (const auto& f : function_table()) {
      if (f.name == request.name) {
        return refuse(protocol::ErrorCode::UnknownFunction,
                      fmt::format("'{}' is an {} function, not {}", f.name, protocol::verb_name(f.verb),
                                  protocol::verb_name(request.verb)));
      }
    }
    return refuse(protocol::ErrorCode::UnknownFunction,
                  fmt::format("no {} function '{}'", protocol::verb_name(request.verb), request.name));
  }
  if (request.args.size() != spec->args.size()) {
    return refuse(protocol::ErrorCode::BadArgument,
                  fmt::format("'{}' takes {} argument{}, got {}", spec->name, spec->args.size(),
                              spec->args.size() == 1 ? "" : "s", request.args.size()));
  }
  std::vector<double> numbers;
  for (std::size_t i = 0; i < request.args.size(); ++i) {
    auto n = request.args[i].number();
    if (!n || !std::isfinite(*n)) {
      return refuse(protocol::ErrorCode::BadArgument,
                    fmt::format("'{}': argument {} ({}) must be a number of {}", spec->name, i + 1, spec->args[i].name,
                                spec->args[i].unit));
    }
    numbers.push_back(*n);
  }
  const std::string& f = spec->name;
  if (f == "setpoint") return from(sim.set_setpoint(numbers[0], numbers[1]));
  if (f == "start_depth_filter") return from(sim.start_depth_filter());
  if (f == "submerge") return from(sim.submerge());
  if (f == "start_timer") return from(sim.start_timer());
  if (f == "surface") return from(sim.surface());
  if (f == "heading") return from(sim.set_heading(numbers[0]));
  if (f == "start_sonar") return from(sim.start_sonar());
  if (f == "stop_sonar") return from(sim.stop_sonar());
  if (f == "goto_depth") return from(sim.goto_depth(numbers[0]));
  if (f == "set_speed") return from(sim.set_speed(numbers[0]));
  if (f == "set_sway") return from(sim.set_sway(numbers[0]));
  if (f == "goto_xy") return from(sim.goto_xy(numbers[0], numbers[1]));
  if (f == "track") return from(sim.track(numbers[0], numbers[1], numbers[2], numbers[3]));
  if (f == "stop") return from(sim.stop());
  if (f == "set_timer") return from(sim.set_timer(numbers[0]));
  if (f == "loiter") return from(sim.loiter(numbers[0], numbers[1], numbers[2]));
  if (f == "hold_position") return from(sim.hold_position());
  if (f == "start_rows") {
    return from(sim.start_rows(numbers[0], numbers[1], numbers[2], numbers[3], numbers[4], numbers[5]));
  }
  if (f == "next_row") {
    // No row to run is the mission's mistake, not the vehicle's failure.
    if (!sim.row_pattern()) return refuse(protocol::ErrorCode::Failed, "next_row: no row pattern (start_rows first)");
    if (sim.rows_done()) {
      return refuse(protocol::ErrorCode::Failed,
                    fmt::format("next_row: no row left (all {} rows started)", sim.row_pattern()->count));
    }
    return from(sim.next_row());
  }
  if (f == "gps_fix") return from(sim.gps_fix());
  if (f == "set_altitude_floor") return from(sim.set_altitude_floor(numbers[0]));
  if (f == "sleep") {
    if (numbers[0] < 0 || numbers[0] > 3600) {
      return refuse(protocol::ErrorCode::BadArgument, "'sleep' takes 0 to 3600 s");
    }
    Outcome o = answer(true);
    o.sleep_s = numbers[0];
    return o;
  }
  if (f == "depth_filter_off") return answer(sim.depth_filter_off());
  if (f == "depth_reached") return answer(sim.depth_reached());
  if (f == "time_out") return answer(sim.time_out());
  if (f == "system_problem") return answer(sim.system_problem());
  if (f == "surface_reached") return answer(sim.surface_reached());
  if (f == "heading_reached") return answer(sim.heading_reached());
  if (f == "target_detected") return answer(sim.target_detected());
  if (f == "waypoint_reached") return answer(sim.waypoint_reached());
  if (f == "altitude_low") return answer(sim.altitude_low());
  if (f == "position_uncertain") return answer(sim.position_uncertain());
  if (f == "gps_available") return answer(sim.gps_available());
  if (f == "rows_done") return answer(sim.rows_done());
  if (f == "start_network") return from(sim.start_network());
  if (f == "shutdown_network") return from(sim.shutdown_network());
  return refuse(protocol::ErrorCode::UnknownFunction, "function table and dispatch disagree: " + f);
}

std::string interface_text() {
  std::string out =
      "strata vehicle: protocol versions 1 and 2, one message per line (docs/protocol.md)\n\n"
      "accepts (client -> vehicle):\n"
      "  hello ID CLIENT_NAME VERSION   -> ok ID VEHICLE_NAME VERSION CLOCK [sonar=PORT]\n"
      "  exec ID FUNCTION [ARG...]      -> done ID 0|1\n"
      "  ask ID PREDICATE [ARG...]      -> answer ID 0|1\n"
      "  ood ID FUNCTION [ARG...]       -> done ID 0|1\n"
      "  telemetry ID RATE_HZ           -> ok ID, then tlm lines at RATE_HZ of sim time (0 stops)\n"
      "  ping ID                        -> pong ID SIM_TIME_S\n"
      "  bye ID                         -> ok ID, then the vehicle closes the link\n"
      "  advance ID                     -> (version 2, lockstep) time moves until a request is due;\n"
      "                                    its replies, then ok ID\n\n"
      "emits (vehicle -> client):\n"
      "  ok, done, answer, pong         replies, carrying the request's id\n"
      "  err ID CODE \"MESSAGE\"          a request that could not be taken (ID 0: unreadable)\n"
      "  tlm SIM_TIME_S depth= fdepth= rate= thrust= setpoint= ...   telemetry; extras in open water:\n"
      "                                 x= y= true_x= true_y= pos_sd= speed= alt=\n"
      "  hb SIM_TIME_S                  heartbeat (wall clock mode, once a second)\n"
      "  event SIM_TIME_S \"TEXT\"        the vehicle's own log: faults, watchdog, failures\n\n"
      "functions:\n";
  for (const auto& f : function_table()) {
    std::string args;
    for (const auto& a : f.args) args += fmt::format(" {}[{}]", a.name, a.unit);
    out += fmt::format("  {:<5} {:<36} {}\n", protocol::verb_name(f.verb), f.name + args, f.doc);
  }
  return out;
}

}  // namespace strata::vehicle
