#pragma once
// The Execution level of the NPS Phoenix in a test tank, simulated: heave
// dynamics, depth cell, depth filter, depth and surface laws, yaw dynamics
// and the heading law, the scanning sonar and its target detector, mission
// timer, scenario faults. One method per Execution-level function the wire protocol
// calls, plus step() to advance one cycle.
//
// Pure and deterministic: no I/O, no threads, no clocks. Time moves only in
// step()/advance(), in whole cycles of params.cycle_s; a simulation built
// from the same params and scenario and driven by the same calls gives the
// same trajectory, bit for bit. Not thread-safe; the owner serialises calls.
//
// Decisions (documented for the protocol server and the missions):
// - Network: until start_network(), every command except start_network and
//   shutdown_network fails ("network not started"); queries always answer.
//   shutdown_network() stops the thrusters (controller idle; the vehicle,
//   positively buoyant, floats up) and is idempotent.
// - Setpoints: set_setpoint() only LOADS the next setpoint; the controller
//   keeps holding the active one until submerge() makes the loaded one
//   active. start_timer() uses the loaded setpoint's timeout.
// - Filter: submerge() is refused while the depth filter is off (the depth
//   law needs a rate estimate; the missions start the filter first). The
//   surface law needs no filter: it uses the raw reading when the filter is
//   off. The filter predicts with the heave model under the thrust the
//   Execution level commanded (through its own model of the thruster lag at
//   nominal strength), so it has no lag while the vehicle accelerates and
//   coasts well through a sensor dropout.
// - depth_reached(): the depth law is engaged, the filter is ready, and
//   |depth - setpoint| < depth_tolerance_m and |rate| < settle_rate_mps.
// - surface_reached(): the depth estimate (filtered if the filter runs, the
//   raw reading otherwise) is <= surface_depth_m; false with no estimate.
// - watchdog_trip(): autonomous surface (surface law) and an event; until
//   start_network() is called again, submerge() is refused.
// - Faults take effect in the step that reaches their at_s: a leak at 2.0 s
//   makes system_problem() true from time_s() == 2.0. weak_thrusters limits
//   the transverse thrusters too.
// - Pose: the vehicle starts at the scenario's (x, y) (tank default: the
//   centre; a position outside the tank is moved to its edge, with an
//   event; open water default: the origin) and at the scenario's heading.
//   It surges only under a guidance command (goto_xy, track, next_row,
//   loiter, hold_position), so the tank missions, which never ask, hover. In the tank the walls stop
//   it (the position is held inside the plan); in open water the current
//   carries it on top of its own speed.
// - Horizontal plane (simulation_horizontal.cpp): goto_xy() and track()
//   engage line-of-sight guidance (guidance.h), which sets the heading law's
//   target every cycle from the ESTIMATED position; stop() stops the motors
//   and the guidance (the heading law holds the heading it had). A waypoint
//   more than kMaxLegM from the estimate, or outside the tank in the tank,
//   is refused.
// - Guidance and speed (issue 37): set_speed() sets the CRUISE speed only:
//   the speed of the guidance commands (goto_xy, track, next_row, loiter,
//   and hold_position's return to its point); it moves nothing by itself,
//   and changes the speed of a guidance running now at once. Unset, the
//   cruise speed is params.cruise_speed_mps; 0 is allowed (the guidance
//   steers but makes no way). stop() keeps it. A waypoint's or a track's
//   guidance ENDS at its goal: waypoint_reached() turns true (latched until
//   the next guidance command or stop) and the vehicle holds the goal point
//   (the hold law, as hold_position). loiter() circles its centre clockwise
//   at the cruise speed until another guidance command; waypoint_reached()
//   there says the circle was reached. hold_position() holds the estimated
//   position of the moment (waypoint_reached() true at once): within
//   waypoint_radius_m it keeps its heading
//   and the speed law drives it along its bow toward the point (astern when
//   past it), off station it turns toward it first.
// - Rows (protocol/rows.h): start_rows() records a lawnmower pattern and
//   resets its cursor; next_row() runs the next row as track() does and
//   moves the cursor; rows_done() is true once every row was started (false
//   with no pattern: a mission that forgot start_rows meets next_row's
//   refusal, not a silent end). The execution table refuses next_row with
//   no row left as a protocol error.
// - system_problem() (issue 37): a fault the vehicle's own sensors report,
//   each latched from its moment to the end of the run (a polled ask cannot
//   miss a short one, and nothing on board clears it): a leak (the leak
//   sensor) and a depth-cell dropout (the cell gives no reading). Weak
//   thrusters are not reported: they still run, only weaker, and the
//   vehicle meets them as a depth not reached in time (Figure 9's time-out).
//   A compass bias is not seen at all; a dead altimeter has altitude_low, a
//   dead GPS receiver gps_available.
// - gps_available(): a fix can be taken now: open water, the receiver works,
//   and the antenna is dry (true depth <= gps_max_depth_m).
// - Sway (sway.h): set_sway() holds a sideways water speed (+ starboard)
//   with the transverse thrusters pushing the same way; the heading law
//   keeps priority (the sway force gets the thrust its moment leaves). The
//   true position moves with it along heading + 90 degrees. stop(),
//   shutdown_network() and watchdog_trip() drop the sway target (force 0).
// - Navigation (navigation.h): dead reckoning every cycle from the water
//   speed and the compass (true heading + compass bias), plus the sway speed
//   of the vehicle's own sway model (the meter measures surge only); in open water a GPS
//   fix every gps_period_s while the true depth is <= gps_max_depth_m and
//   the receiver works; gps_fix() takes one at once (refused below the
//   surface or with no GPS). In the tank the estimate is the truth.
//   position_uncertain(): the estimate's horizontal 1-sigma exceeds
//   position_limit_m.
// - Altimeter: the true altitude above the seabed (the tank's floor in the
//   tank) plus noise, or none beyond altimeter_range_m or once dead.
//   altitude_low(): a reading below the altitude floor, or a dead altimeter
//   while submerged (a vehicle that cannot see the bottom must not go on).
// - goto_depth(d): starts the depth filter if it is off, loads d with no
//   time limit and engages the depth law, in one call. In open water depths
//   go to max_depth_m (the tank: tank_depth_m); the seabed stops the vehicle.
// - Heading (yaw.h): set_heading() engages the heading law toward its
//   heading; the depth law runs independently. With no heading commanded the
//   transverse thrusters are off. shutdown_network() and watchdog_trip()
//   disengage it; set_heading() is refused after a watchdog trip, like
//   submerge(). heading_reached(): the heading law is engaged and |error| <
//   heading_tolerance_deg and |yaw rate| < heading_settle_dps.
// - Sonar (sonar.h): start_sonar()/stop_sonar() need the network;
//   shutdown_network() stops it. Pings come at sub-step resolution during
//   step() and wait in a bounded buffer for take_pings(). target_detected()
//   is false while the sonar is off.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "protocol/rows.h"
#include "vehicle/depth_cell.h"
#include "vehicle/depth_filter.h"
#include "vehicle/guidance.h"
#include "vehicle/heave.h"
#include "vehicle/navigation.h"
#include "vehicle/params.h"
#include "vehicle/scenario.h"
#include "vehicle/sonar.h"
#include "vehicle/surge.h"
#include "vehicle/sway.h"
#include "vehicle/yaw.h"

namespace strata::vehicle {

enum class ControlMode {
  Idle,     // thrusters off
  Depth,    // sliding-mode law toward the active setpoint
  Surface,  // surface law (commanded, or autonomous after a watchdog trip)
};

std::string_view to_string(ControlMode mode);

struct Event {
  double time_s = 0.0;
  std::string text;  // e.g. "fault: leak started", "watchdog: link silent 3.0 s: surfacing"

  bool operator==(const Event&) const = default;
};

struct FaultState {
  bool leak = false;
  double thrust_health = 1.0;     // fraction of nominal thrust available
  bool sensor_dropout = false;    // the depth cell gives no reading now
  bool link_lost = false;         // the scenario says the link is silent now
  double compass_bias_deg = 0.0;  // compass reading - true heading
  bool altimeter_dead = false;
  bool no_gps = false;
  // Detected on board, latched to the end of the run (system_problem):
  bool depth_cell_fault = false;  // a depth-cell dropout

  bool operator==(const FaultState&) const = default;
};

struct Telemetry {
  double time_s = 0.0;
  double depth_m = 0.0;                        // true depth
  double w_mps = 0.0;                          // true heave rate
  std::optional<double> measured_depth_m;      // last depth cell reading (none in a dropout)
  std::optional<double> filtered_depth_m;      // filter output (none while off or not ready)
  std::optional<double> rate_mps;              // filtered depth rate
  double thrust_n = 0.0;                       // actual total thrust
  double thrust_cmd_n = 0.0;                   // commanded total thrust
  std::optional<double> setpoint_m;            // the depth the controller drives to (0 when surfacing)
  double heading_deg = 0.0;                    // true compass heading, [0, 360)
  double yaw_rate_dps = 0.0;                   // true yaw rate, clockwise positive
  double yaw_moment_nm = 0.0;                  // actual moment of the transverse thrusters
  double yaw_moment_cmd_nm = 0.0;              // commanded moment
  std::optional<double> heading_setpoint_deg;  // the heading law's target (none: idle)
  double x_m = 0.0, y_m = 0.0;                 // estimated position (navigation)
  double true_x_m = 0.0, true_y_m = 0.0;       // true position
  double position_sd_m = 0.0;                  // the estimate's horizontal 1-sigma
  double speed_mps = 0.0;                      // true speed through the water
  std::optional<double> speed_setpoint_mps;    // the speed law's target (none: motors off)
  std::optional<double> altitude_m;            // altimeter reading (none: no echo, or dead)
  GuidanceMode guidance = GuidanceMode::None;
  bool open_water = false;
  bool sonar_on = false;
  bool filter_on = false;
  ControlMode mode = ControlMode::Idle;
  bool network_up = false;
  bool watchdog_tripped = false;
  FaultState faults;

  bool operator==(const Telemetry&) const = default;
};

class Simulation {
 public:
  // The vehicle starts at rest at the surface, thrusters off, filter off,
  // network down. Faults with at_s <= 0 apply at once.
  Simulation(VehicleParams params, Scenario scenario);

  // ---- commands: ok, or ErrorCode::InvalidInput with a reason -------------
  core::Result<void> start_network();
  core::Result<void> shutdown_network();
  // depth_m in [0, tank_depth_m], timeout_s > 0.
  core::Result<void> set_setpoint(double depth_m, double timeout_s);
  core::Result<void> start_depth_filter();
  core::Result<void> submerge();
  core::Result<void> start_timer();
  // The manoeuvre timer with its own limit, seconds > 0 (start_timer uses
  // the loaded setpoint's).
  core::Result<void> set_timer(double seconds);
  core::Result<void> surface();
  // Engages the heading law toward heading_deg (compass, [0, 360]; 360 is 0).
  core::Result<void> set_heading(double heading_deg);
  core::Result<void> start_sonar();
  core::Result<void> stop_sonar();
  // Horizontal plane and navigation (see the decisions above).
  core::Result<void> set_speed(double speed_mps);  // [0, top speed]
  core::Result<void> set_sway(double speed_mps);   // [-top sway speed, top sway speed], + starboard
  core::Result<void> goto_xy(double x_m, double y_m);
  core::Result<void> track(double x0_m, double y0_m, double x1_m, double y1_m);
  core::Result<void> stop();
  // Circle (x, y) at radius_m (>= kMinLoiterRadiusM), clockwise, at the cruise speed.
  core::Result<void> loiter(double x_m, double y_m, double radius_m);
  // Hold the estimated position of now (station keeping).
  core::Result<void> hold_position();
  // A lawnmower pattern (protocol/rows.h), cursor at its first row; no motion.
  core::Result<void> start_rows(double x_m, double y_m, double heading_deg, double length_m, double spacing_m,
                                double count);
  // track() along the next row; an error with no pattern or no row left.
  core::Result<void> next_row();
  core::Result<void> goto_depth(double depth_m);
  core::Result<void> gps_fix();
  core::Result<void> set_altitude_floor(double floor_m);  // [0, altimeter range]
  // Autonomous surface with an event "watchdog: <reason>: surfacing". The
  // protocol server calls it after watchdog_s of link silence. Repeated trips
  // record nothing new.
  void watchdog_trip(std::string_view reason);

  // ---- queries ------------------------------------------------------------
  bool depth_filter_off() const { return !filter_.on(); }
  bool depth_reached() const;
  bool time_out() const;
  bool surface_reached() const;
  bool system_problem() const { return faults_.leak || faults_.depth_cell_fault; }
  bool gps_available() const;
  bool rows_done() const { return rows_.has_value() && next_row_ >= rows_->count; }
  const std::optional<protocol::RowPattern>& row_pattern() const { return rows_; }
  int rows_started() const { return next_row_; }
  // The cruise speed of the guidance commands (set_speed, else the params').
  double cruise_speed_mps() const { return cruise_mps_.value_or(params_.cruise_speed_mps); }
  bool heading_reached() const;
  bool sonar_on() const { return sonar_.on(); }
  bool target_detected() const { return sonar_.target_detected(); }
  bool waypoint_reached() const { return reached_; }
  bool altitude_low() const;
  bool position_uncertain() const { return nav_.position_sd_m() > params_.position_limit_m; }
  std::optional<double> altitude_m() const { return altitude_m_; }
  const Navigator& navigator() const { return nav_; }
  const Guidance& guidance() const { return guidance_; }
  const SurgeState& surge() const { return surge_; }
  const SwayState& sway() const { return sway_; }
  // The sway law's target (none: not asked since the last stop) and force
  // command this cycle, after the heading law took its share.
  std::optional<double> sway_setpoint_mps() const { return sway_target_mps_; }
  double sway_force_cmd_n() const { return sway_force_cmd_n_; }
  // Navigation's sway speed: the vehicle's own model of its sway (sway.h at
  // nominal thrust, from the commanded force); the water-speed meter
  // measures surge only.
  double sway_model_mps() const { return sway_model_.speed_mps; }
  bool open_water() const { return scenario_.world.open_water; }
  bool network_up() const { return network_up_; }
  bool watchdog_tripped() const { return watchdog_tripped_; }
  // Link loss, for the protocol server (the simulation itself ignores it).
  bool link_lost() const { return faults_.link_lost; }
  std::optional<double> link_lost_at() const { return scenario_.link_lost_at(); }

  // ---- time -----------------------------------------------------------------
  // One cycle of params.cycle_s: control, dynamics, faults, sensing, filter.
  void step();
  // round(seconds / cycle_s) cycles (none for seconds <= 0); returns the count.
  std::uint64_t advance(double seconds);
  double time_s() const { return static_cast<double>(cycle_) * params_.cycle_s; }
  std::uint64_t cycle() const { return cycle_; }

  Telemetry telemetry() const;
  // Events since construction, in time order; take_events() hands them over
  // and clears the list.
  const std::vector<Event>& events() const { return events_; }
  std::vector<Event> take_events();
  // The sonar's pings since the last call, oldest first (sonar.h); seq
  // counts every ping made, so a gap is a ping dropped from a full buffer.
  std::vector<protocol::SonarPing> take_pings() { return sonar_.take_pings(); }
  std::uint64_t pings_dropped() const { return sonar_.dropped(); }

  const VehicleParams& params() const { return params_; }
  const Scenario& scenario() const { return scenario_; }
  const HeaveState& heave() const { return heave_; }
  const YawState& yaw() const { return yaw_; }
  Pose pose() const { return {x_m_, y_m_, yaw_.heading_deg}; }

 private:
  struct Setpoint {
    double depth_m;
    double timeout_s;
  };
  struct Timer {
    double start_s;
    double timeout_s;
  };

  core::Result<void> require_network() const;
  std::optional<double> depth_estimate() const;
  double control() const;
  double expected_accel_mps2() const;
  void place_vehicle();
  void advance_yaw_and_sonar();
  // simulation_horizontal.cpp
  core::Result<void> check_goal(double x_m, double y_m) const;
  core::Result<void> engage(Guidance g);
  double compass_deg() const;
  void guide();
  void hold();
  void move_substep(double h_s, double motor_lag, double transverse_lag);
  void navigate();
  double bottom_m() const;
  void apply_faults();
  void sense();
  void event(std::string text);

  VehicleParams params_;
  Scenario scenario_;
  DepthCell cell_;
  DepthFilter filter_;
  HeaveState heave_;
  YawState yaw_;
  Sonar sonar_;
  double x_m_ = 0.0;
  double y_m_ = 0.0;
  std::uint64_t cycle_ = 0;

  ControlMode mode_ = ControlMode::Idle;
  bool network_up_ = false;
  bool watchdog_tripped_ = false;
  std::optional<Setpoint> loaded_;
  std::optional<double> active_setpoint_m_;
  std::optional<Timer> timer_;
  std::optional<double> reading_m_;
  double thrust_cmd_n_ = 0.0;
  double thrust_model_n_ = 0.0;
  std::optional<double> heading_target_deg_;
  double moment_cmd_nm_ = 0.0;

  SurgeState surge_;
  std::optional<double> speed_target_mps_;  // the speed law's target now (none: motors never run)
  std::optional<double> cruise_mps_;        // set_speed's
  std::optional<protocol::RowPattern> rows_;
  int next_row_ = 0;
  SwayState sway_, sway_model_;
  std::optional<double> sway_target_mps_;
  double sway_force_cmd_n_ = 0.0;  // this cycle's, after the heading law's share
  double sway_model_cmd_n_ = 0.0;  // the same for the vehicle's own model (nominal thrusters)
  Guidance guidance_;
  bool reached_ = false;
  Navigator nav_;
  DepthCell gps_x_noise_, gps_y_noise_, altimeter_noise_;
  double next_gps_s_ = 0.0;
  std::optional<double> altitude_m_;
  double altitude_floor_m_;

  FaultState faults_;
  std::vector<bool> fault_applied_;
  std::optional<double> dropout_until_s_;
  bool at_bottom_ = false;

  std::vector<Event> events_;
};

// The longest leg goto_xy and track accept, m: a farther goal is refused.
inline constexpr double kMaxLegM = 20000.0;
// The smallest loiter circle, m: the heading law turns the Phoenix about
// 10 deg/s at most, a 5 m circle at 0.8 m/s.
inline constexpr double kMinLoiterRadiusM = 5.0;

}  // namespace strata::vehicle
