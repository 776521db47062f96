#pragma once
// What the IMC codec's tests share: a packet of every message type, and
// datagrams built by hand (header, payload, a CRC computed here bit by bit,
// independently of the codec's table).
#include <cstdint>
#include <string>
#include <vector>

#include "imc/codec.h"

namespace strata::imc::testing {

// CRC-16-IBM as the specification states it: reflected polynomial 0xA001,
// initial 0, one bit at a time.
inline std::uint16_t bitwise_crc16(const std::vector<std::uint8_t>& bytes) {
  std::uint16_t crc = 0;
  for (std::uint8_t b : bytes) {
    crc = static_cast<std::uint16_t>(crc ^ b);
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 1u) ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001u) : static_cast<std::uint16_t>(crc >> 1);
    }
  }
  return crc;
}

// `bytes` with its CRC appended, low byte first.
inline std::vector<std::uint8_t> with_crc(std::vector<std::uint8_t> bytes) {
  const std::uint16_t crc = bitwise_crc16(bytes);
  bytes.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  bytes.push_back(static_cast<std::uint8_t>(crc >> 8));
  return bytes;
}

// A datagram for `payload` under message id `mgid`: the header written
// byte by byte (timestamp 1.5 s, from 0x4001/5 to 0x00D1/0xFF), the size
// field `size` (the payload's length unless given), the CRC.
inline std::vector<std::uint8_t> datagram(std::uint16_t mgid, const std::vector<std::uint8_t>& payload, int size = -1) {
  const auto n = static_cast<std::uint16_t>(size < 0 ? payload.size() : static_cast<std::size_t>(size));
  std::vector<std::uint8_t> out = {
      0x54,
      0xFE,  // sync 0xFE54
      static_cast<std::uint8_t>(mgid & 0xFF),
      static_cast<std::uint8_t>(mgid >> 8),
      static_cast<std::uint8_t>(n & 0xFF),
      static_cast<std::uint8_t>(n >> 8),
      0x00,
      0x00,
      0x00,
      0x00,
      0x00,
      0x00,
      0xF8,
      0x3F,  // timestamp 1.5
      0x01,
      0x40,  // src 0x4001
      0x05,  // src_ent 5
      0xD1,
      0x00,  // dst 0x00D1
      0xFF,  // dst_ent 0xFF
  };
  out.insert(out.end(), payload.begin(), payload.end());
  return with_crc(std::move(out));
}

// The header datagram() writes.
inline Header test_header() {
  Header h;
  h.timestamp = 1.5;
  h.src = 0x4001;
  h.src_ent = 5;
  h.dst = 0x00D1;
  h.dst_ent = 0xFF;
  return h;
}

// The plan Strata starts on a DUNE vehicle: one FollowReference manoeuvre.
inline PlanControl follow_reference_plan() {
  FollowReference fr;
  fr.control_src = 0x4001;
  fr.control_ent = 5;
  fr.timeout = 10.0f;
  fr.loiter_radius = 5.0f;
  fr.altitude_interval = 1.0f;
  PlanManeuver pm;
  pm.maneuver_id = "m";
  pm.data = fr;
  PlanSpecification spec;
  spec.plan_id = "p";
  spec.start_man_id = "m";
  spec.maneuvers.push_back(pm);
  PlanControl pc;
  pc.type = PlanControl::kRequest;
  pc.op = PlanControl::kStart;
  pc.request_id = 7;
  pc.plan_id = "p";
  pc.arg = spec;
  return pc;
}

inline Reference sample_reference() {
  Reference r;
  r.flags = Reference::kFlagLocation | Reference::kFlagSpeed | Reference::kFlagZ;
  r.speed = DesiredSpeed{1.5, DesiredSpeed::kSpeedUnitsMetersPs};
  r.z = DesiredZ{2.0f, DesiredZ::kZUnitsDepth};
  r.lat = 0.5;
  r.lon = -0.25;
  return r;
}

inline EstimatedState sample_estimated_state() {
  EstimatedState s;
  s.lat = 0.7188;
  s.lon = -0.1531;
  s.x = 12.5f;
  s.y = -3.25f;
  s.z = 2.0f;
  s.psi = 1.2f;
  s.u = 1.4f;
  s.depth = 2.0f;
  s.alt = 17.5f;
  return s;
}

// One packet of every message of messages.def, each field away from its
// default where it has one, in the table's order.
inline std::vector<Packet> every_message() {
  const Header h = test_header();
  std::vector<Packet> out;
  out.push_back({h, EntityState{EntityState::kStateError, EntityState::kFlagHumanIntervention, "leak"}});
  out.push_back({h, EntityList{EntityList::kOpReport, "Daemon=0;Leak Sensor - Nose=7"}});
  out.push_back({h, LogBookEntry{LogBookEntry::kTypeError, 1.7e9, "Plan", "reference source timed out"}});
  out.push_back({h, Heartbeat{}});
  out.push_back(
      {h, Announce{"strata", Announce::kSysTypeCcu, 0xFFFF, 0.7188, -0.1531, 0.0f, "imc+udp://127.0.0.1:6002/"}});
  out.push_back({h, EntityParameter{"Active", "true"}});
  out.push_back({h, SetEntityParameters{"Leak Sensor - Nose", {{"Active", "true"}, {"Threshold", "0.5"}}}});
  GpsFix fix;
  fix.validity = 0x1FF;
  fix.type = GpsFix::kTypeSimulation;
  fix.utc_year = 2025;
  fix.utc_month = 6;
  fix.utc_day = 30;
  fix.utc_time = 43200.5f;
  fix.lat = 0.7188;
  fix.lon = -0.1531;
  fix.satellites = 9;
  fix.hdop = 0.9f;
  out.push_back({h, fix});
  out.push_back({h, sample_estimated_state()});
  NavigationUncertainty nu;
  nu.x = 0.25f;
  nu.y = 0.5f;
  nu.z = 0.01f;
  nu.psi = 0.002f;
  nu.r = 1e-4f;
  nu.u = 0.05f;
  nu.bias_psi = 3e-3f;
  nu.bias_r = 2e-5f;
  out.push_back({h, nu});
  out.push_back({h, DesiredZ{2.0f, DesiredZ::kZUnitsDepth}});
  out.push_back({h, DesiredSpeed{1.2, DesiredSpeed::kSpeedUnitsMetersPs}});
  out.push_back({h, FollowReference{0x4001, 5, 10.0f, 5.0f, 1.0f}});
  out.push_back({h, sample_reference()});
  out.push_back(
      {h, FollowRefState{0x4001, 5, sample_reference(), FollowRefState::kStateGoto, FollowRefState::kProxFar}});
  VehicleState vs;
  vs.op_mode = VehicleState::kOpModeError;
  vs.error_count = 1;
  vs.error_ents = "Leak Sensor - Nose";
  vs.maneuver_type = FollowReference::kId;
  vs.maneuver_stime = 1.7e9;
  vs.maneuver_eta = 0xFFFF;
  vs.control_loops = VehicleState::kLoopPath | VehicleState::kLoopDepth;
  vs.last_error = "Leak Sensor - Nose: leak detected";
  vs.last_error_time = 1.7e9 + 3;
  out.push_back({h, vs});
  out.push_back({h, MonitorEntityState{MonitorEntityState::kCommandEnable, "Leak Sensor - Nose"}});
  out.push_back({h, Abort{}});
  out.push_back({h, PlanVariable{"depth", "2.0", PlanVariable::kTypeNumber, PlanVariable::kAccessInput}});
  PlanManeuver pm;
  pm.maneuver_id = "m";
  pm.data = FollowReference{0x4001, 5, 10.0f, 5.0f, 1.0f};
  pm.start_actions.emplace_back(Inline(EntityList{EntityList::kOpQuery, ""}));
  pm.end_actions.emplace_back(Inline());
  out.push_back({h, pm});
  out.push_back({h, PlanTransition{"m", "_done_", "ManeuverIsDone", {Inline(Heartbeat{})}}});
  PlanSpecification spec = std::get<PlanSpecification>(*follow_reference_plan().arg.get());
  spec.description = "one reference";
  spec.variables.push_back(PlanVariable{"speed", "1.2", PlanVariable::kTypeNumber, PlanVariable::kAccessLocal});
  spec.transitions.push_back(PlanTransition{"m", "_done_", "ManeuverIsDone", {}});
  spec.end_actions.emplace_back(Inline(Abort{}));
  out.push_back({h, spec});
  Packet plan{h, follow_reference_plan()};
  plan.header.dst = kAnyVehicle;
  out.push_back(plan);
  out.push_back({h, PlanControlState{PlanControlState::kStateExecuting, "p", -1, 12.5f, "m", FollowReference::kId, -1,
                                     PlanControlState::kLastOutcomeSuccess}});
  return out;
}

}  // namespace strata::imc::testing
