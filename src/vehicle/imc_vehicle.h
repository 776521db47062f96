#pragma once
// The simulated Phoenix as an IMC vehicle, without the socket: what it does
// with the messages a controller sends (PlanControl, Reference, Abort) and
// what it says back and streams, cycle by cycle (docs/imc.md, "strata
// vehicle --imc"; the contract the IMC link is written against is the same
// text). ImcVehicleServer (imc_server.h) puts it behind a UDP socket: it
// keeps the peers, filters what reaches here, and sends the outbox to every
// announced peer.
//
// It drives the Simulation through its own commands (goto_xy, set_speed,
// goto_depth, surface, stop, watchdog_trip), as the Phoenix protocol's
// functions do; no physics here. Coordinates: the Simulation's x is east and
// y north (the tank's plan in the tank); IMC's x is north, y east, from the
// navigation origin (lat0, lon0): IMC (x, y) = Simulation (y, x).
//
// Decisions (where DUNE's FollowReference is followed, and where not):
// - The vehicle's network is started at construction: an IMC vehicle is on.
// - A plan is one FollowReference manoeuvre; PlanControl START with anything
//   else fails ("only a FollowReference plan..."). A START replaces a running
//   plan (its controller hears nothing more, as in DUNE).
// - A Reference steers: LOCATION is a goto (line-of-sight guidance); once
//   the guidance reaches the point (waypoint_radius_m) the motors stop and
//   the vehicle holds there, re-engaging if it drifts more than
//   kHoldRadiusM away. SPEED in m/s (or percent of the top speed) is clamped
//   to [0, top speed]; 0 stops the motors. Z in DEPTH units: > 0 is
//   goto_depth (clamped to the deepest depth the vehicle accepts), 0 is the
//   surface law. A point outside the tank is moved onto its edge; one more
//   than kMaxLegM away is refused (logged, the previous goal kept).
// - The end of a plan (MANDONE, STOP, the reference timeout, a fault) turns
//   every control loop off (the Phoenix, slightly positively buoyant, floats
//   up slowly), as DUNE's SERVICE does. An Abort instead surfaces the
//   vehicle with the surface law (the Phoenix watchdog's surfacing).
// - Errors: a leak, weak thrusters, a depth cell dropout and a dead
//   altimeter are errors of an entity while they last; a compass bias and a
//   dead GPS receiver are not (the vehicle cannot tell). A plan that starts
//   in error fails at the next cycle (DUNE: 1.1 s later).
// Pure and deterministic: no I/O, no clocks; not thread-safe.
#include <cstdint>
#include <functional>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "imc/codec.h"
#include "imc/message.h"
#include "vehicle/simulation.h"

namespace strata::vehicle {

// The header timestamp of simulated time 0 (seconds): timestamps are this
// plus simulated seconds, so they look like Unix times and move with --speed.
inline constexpr double kImcEpochS = 1.7e9;
// The fixed navigation origin: 41.18 N, 8.70 W (off Porto), in radians. In
// the tank it is the tank's corner (0, 0).
inline constexpr double kImcOriginLatRad = 41.18 * std::numbers::pi / 180.0;
inline constexpr double kImcOriginLonRad = -8.70 * std::numbers::pi / 180.0;
// WGS-84 equatorial radius, for the flat-earth conversion (contract).
inline constexpr double kEarthRadiusM = 6378137.0;
// FollowRefState proximity: XY_NEAR within this plus Reference.radius
// (horizontal), Z_NEAR within kZNearM of the reference's z.
inline constexpr double kXyNearM = 15.0;
inline constexpr double kZNearM = 1.0;
// Holding a reached point: the guidance re-engages beyond this distance.
inline constexpr double kHoldRadiusM = 7.5;
// Abort: VehicleState ERROR for this long, simulated seconds.
inline constexpr double kAbortErrorS = 1.0;

struct ImcVehicleOptions {
  std::uint16_t imc_id = 0x2C01;
  double origin_lat_rad = kImcOriginLatRad;
  double origin_lon_rad = kImcOriginLonRad;
  // The vehicle's own log ("12.3 s: plan 'x' started by 0x4001"): events of
  // the simulation, plans, references ignored or clamped.
  std::function<void(const std::string&)> log;
};

// A message to send to every announced peer, with the header's destination.
struct ImcOutgoing {
  imc::Message message;
  std::uint16_t dst = imc::kNullId;
  std::uint8_t dst_ent = imc::kAnyEntity;
};

struct ImcVehicleCounts {
  std::uint64_t references = 0;          // References applied
  std::uint64_t references_ignored = 0;  // no plan executing, or not the plan's control source
  std::uint64_t requests_ignored = 0;    // PlanControl / Abort addressed to another system
  std::uint64_t clamped = 0;             // References whose point, depth or speed was clamped
};

class ImcVehicle {
 public:
  // sim outlives this object; its network is started here.
  ImcVehicle(Simulation& sim, ImcVehicleOptions options);

  // A packet from an announced peer (the server filtered the rest):
  // PlanControl requests, References and Abort act; others are ignored.
  void receive(const imc::Header& header, const imc::Message& message);
  // One cycle: the simulation steps, then the plan's timeout, faults and
  // holding; then the streams due at the new time (NavigationUncertainty and
  // EstimatedState every cycle, in that order, so that an ask answered at an
  // EstimatedState sees the uncertainty of its cycle; VehicleState and
  // PlanControlState at 2 Hz; GpsFix and Heartbeat at 1 Hz).
  void step();
  // What to send, in order; the list is handed over and cleared.
  std::vector<ImcOutgoing> take_outbox();

  double timestamp() const { return kImcEpochS + sim_.time_s(); }
  const ImcVehicleCounts& counts() const { return counts_; }
  bool plan_executing() const { return plan_.has_value(); }
  // The IMC id that steers the running plan (kNullId: any), if one runs.
  std::optional<std::uint16_t> plan_controller() const {
    return plan_ ? std::optional<std::uint16_t>(plan_->control_src) : std::nullopt;
  }

  // The messages as they would be sent now.
  imc::EstimatedState estimated_state() const;
  void on_entity_parameters(const imc::SetEntityParameters& set);
  imc::VehicleState vehicle_state() const;
  imc::PlanControlState plan_control_state() const;
  imc::GpsFix gps_fix() const;
  // The position estimate's variance (navigation.h), the same on x and y.
  imc::NavigationUncertainty navigation_uncertainty() const;
  // (lat, lon) radians of a Simulation point (x east, y north), and back.
  std::pair<double, double> to_lat_lon(double x_east_m, double y_north_m) const;
  std::pair<double, double> to_plan(double lat_rad, double lon_rad) const;

 private:
  struct Plan {
    std::string plan_id;
    std::string maneuver_id;
    std::uint16_t request_id = 0;
    std::uint16_t requester = imc::kNullId;
    std::uint8_t requester_ent = imc::kAnyEntity;
    std::uint16_t control_src = imc::kNullId;
    std::uint8_t control_ent = imc::kAnyEntity;
    double timeout_s = 0.0;
    double start_s = 0.0;
    double last_reference_s = 0.0;
    std::optional<imc::Reference> reference;  // the last one followed
    // The goal, in the Simulation's plan, once a Reference gave a location.
    std::optional<std::pair<double, double>> goal;
    double speed_mps = 0.0;         // the speed the goal is driven at
    bool holding = false;           // at the goal, motors stopped
    std::optional<double> depth_m;  // z asked (0: the surface)
  };
  struct ErrorEntity {
    std::string entity;  // "Leak Sensor - Nose"
    std::string text;    // "leak detected"
  };

  void on_plan_control(const imc::Header& h, const imc::PlanControl& pc);
  void start_plan(const imc::Header& h, const imc::PlanControl& pc);
  void on_reference(const imc::Header& h, const imc::Reference& ref);
  void on_abort(const imc::Header& h);
  void reply(const imc::Header& to, const imc::PlanControl& request, std::uint8_t type, std::string info);
  // Ends the plan: a PlanControl to its requester (type, info), the outcome,
  // and every control loop off.
  void end_plan(std::uint8_t type, std::string info, std::uint8_t outcome);
  void loops_off();
  void drive();  // the goal, holding and speed, each cycle
  void check_errors();
  std::vector<ErrorEntity> errors_now() const;
  bool in_error() const;
  std::uint8_t proximity() const;
  std::uint8_t follow_state() const;
  imc::FollowRefState follow_ref_state(std::uint8_t state) const;
  double depth_now() const;
  double horizontal_distance_m() const;
  void send(imc::Message m, std::uint16_t dst = imc::kNullId, std::uint8_t dst_ent = imc::kAnyEntity);
  void log(const std::string& line) const;
  mutable std::string last_line_;  // log(): a repeat of it is counted, not written
  mutable std::uint64_t repeats_ = 0;
  void flush_events();

  Simulation& sim_;
  ImcVehicleOptions options_;
  std::optional<Plan> plan_;
  // The last plan's id and outcome, for PlanControlState.
  std::string last_plan_id_;
  std::uint8_t last_outcome_ = 0;
  std::vector<ErrorEntity> errors_;  // the entities in error at the last cycle
  std::string last_error_;
  double last_error_time_ = 0.0;
  std::optional<double> abort_until_s_;  // VehicleState ERROR "got abort request" until then
  ImcVehicleCounts counts_;
  std::vector<ImcOutgoing> outbox_;
};

}  // namespace strata::vehicle
