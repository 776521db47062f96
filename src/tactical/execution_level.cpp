#include "tactical/execution_level.h"

#include <array>

#include <fmt/format.h>

#include "tactical/message_template.h"

namespace strata::tactical {
namespace {

struct ImcRow {
  protocol::Verb verb;
  std::string_view function;
  ImcMapping mapping;
};

// docs/imc.md, "The mapping": one row per wire function an IMC vehicle carries.
constexpr std::array kImcTable{
    ImcRow{protocol::Verb::Exec, "setpoint", ImcMapping::Local},
    ImcRow{protocol::Verb::Exec, "start_depth_filter", ImcMapping::Local},
    ImcRow{protocol::Verb::Exec, "submerge", ImcMapping::Reference},
    ImcRow{protocol::Verb::Exec, "start_timer", ImcMapping::Local},
    ImcRow{protocol::Verb::Exec, "set_timer", ImcMapping::Local},
    ImcRow{protocol::Verb::Exec, "sleep", ImcMapping::Local},
    ImcRow{protocol::Verb::Exec, "surface", ImcMapping::Reference},
    ImcRow{protocol::Verb::Exec, "heading", ImcMapping::Reference},
    ImcRow{protocol::Verb::Exec, "goto_depth", ImcMapping::Reference},
    ImcRow{protocol::Verb::Exec, "set_speed", ImcMapping::Reference},
    ImcRow{protocol::Verb::Exec, "goto_xy", ImcMapping::Reference},
    ImcRow{protocol::Verb::Exec, "track", ImcMapping::Reference},
    ImcRow{protocol::Verb::Exec, "stop", ImcMapping::Reference},
    ImcRow{protocol::Verb::Exec, "hold_position", ImcMapping::Reference},
    ImcRow{protocol::Verb::Exec, "start_rows", ImcMapping::Local},
    ImcRow{protocol::Verb::Exec, "next_row", ImcMapping::Reference},
    ImcRow{protocol::Verb::Exec, "gps_fix", ImcMapping::State},
    ImcRow{protocol::Verb::Exec, "set_altitude_floor", ImcMapping::Local},
    ImcRow{protocol::Verb::Exec, "start_sonar", ImcMapping::Payload},
    ImcRow{protocol::Verb::Exec, "stop_sonar", ImcMapping::Payload},
    ImcRow{protocol::Verb::Ask, "depth_filter_off", ImcMapping::Local},
    ImcRow{protocol::Verb::Ask, "depth_reached", ImcMapping::State},
    ImcRow{protocol::Verb::Ask, "time_out", ImcMapping::Local},
    ImcRow{protocol::Verb::Ask, "system_problem", ImcMapping::State},
    ImcRow{protocol::Verb::Ask, "surface_reached", ImcMapping::State},
    ImcRow{protocol::Verb::Ask, "heading_reached", ImcMapping::State},
    ImcRow{protocol::Verb::Ask, "waypoint_reached", ImcMapping::State},
    ImcRow{protocol::Verb::Ask, "altitude_low", ImcMapping::State},
    ImcRow{protocol::Verb::Ask, "position_uncertain", ImcMapping::State},
    ImcRow{protocol::Verb::Ask, "gps_available", ImcMapping::State},
    ImcRow{protocol::Verb::Ask, "rows_done", ImcMapping::Local},
    ImcRow{protocol::Verb::Ood, "start_network", ImcMapping::Plan},
    ImcRow{protocol::Verb::Ood, "shutdown_network", ImcMapping::Plan},
};

// Why an IMC vehicle has nothing for a wire function the Phoenix carries.
std::string imc_refusal(std::string_view function) {
  if (function == "target_detected") {
    return "an IMC vehicle sends no sonar sweeps on this link (the Phoenix's sonar socket has no IMC counterpart)";
  }
  if (function == "set_sway") return "an IMC vehicle takes no sideways speed (a Reference has none)";
  if (function == "loiter") {
    return "an IMC vehicle's FollowReference cannot circle a point of the mission's choosing (its loiter radius is "
           "fixed when the plan starts, and used only once a Reference's point is reached)";
  }
  return fmt::format("an IMC vehicle has no counterpart for '{}' (docs/imc.md lists what it carries)", function);
}

}  // namespace

std::string_view execution_level_name(ExecutionLevel level) {
  return level == ExecutionLevel::Imc ? "an IMC vehicle" : "the Phoenix protocol";
}

ExecutionLevel execution_level_of(std::string_view vehicle) {
  constexpr std::string_view kScheme = "imc://";  // a scheme is case-insensitive (RFC 3986)
  if (vehicle.size() < kScheme.size()) return ExecutionLevel::Phoenix;
  for (std::size_t i = 0; i < kScheme.size(); ++i) {
    const char c = vehicle[i];
    if ((c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c) != kScheme[i]) return ExecutionLevel::Phoenix;
  }
  return ExecutionLevel::Imc;
}

std::optional<ImcMapping> imc_mapping(protocol::Verb verb, std::string_view function) {
  for (const ImcRow& row : kImcTable) {
    if (row.verb == verb && row.function == function) return row.mapping;
  }
  return std::nullopt;
}

std::optional<std::string> unavailable_on(ExecutionLevel level, const Primitive& primitive) {
  if (level == ExecutionLevel::Phoenix || primitive.kind == Kind::Report) return std::nullopt;
  auto parsed = parse_message_template(primitive.message);
  if (!parsed || parsed.value().fields.size() < 2 || !parsed.value().fields[1].is_literal()) {
    return fmt::format("its message `{}` names no wire function an IMC vehicle could map", primitive.message);
  }
  const std::string& function = parsed.value().fields[1].pieces[0].text;
  const protocol::Verb verb = primitive.kind == Kind::Ask   ? protocol::Verb::Ask
                              : primitive.kind == Kind::Ood ? protocol::Verb::Ood
                                                            : protocol::Verb::Exec;
  if (imc_mapping(verb, function)) return std::nullopt;
  return imc_refusal(function);
}

}  // namespace strata::tactical
