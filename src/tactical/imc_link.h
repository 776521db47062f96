#pragma once
// The Tactical level's link to an IMC vehicle (LSTS DUNE's LAUV, or
// `strata vehicle --imc`) over UDP: the ExecutionLink for `--vehicle
// imc://HOST:PORT`. docs/imc.md is the reference; in short:
//
//  - Heard: it announces itself (Announce, then Heartbeat each wall second),
//    learns the vehicle's IMC id from the vehicle's Announce (or is given
//    it), waits for the first EstimatedState (the navigation origin and the
//    start of the run's clock), then starts one PlanControl plan holding a
//    FollowReference manoeuvre that names this link as its controller.
//  - Steering: exec requests change a desired state (location, speed, depth)
//    sent as a Reference at once and again every reference_period_s of the
//    vehicle's time, so the vehicle's FollowReference never times out while
//    the run lives. Local functions (setpoints, the timer, the filter flag,
//    sleep) are kept here on the vehicle's clock. The table of what each
//    primitive does is tactical/execution_level.cpp and docs/imc.md.
//  - Answers: every exec/ask/ood is answered at the next EstimatedState after
//    it (one vehicle cycle, as the Phoenix answers at the end of its cycle),
//    asks from the state then; `sleep N` at the first one N seconds on.
//  - Clock: the vehicle's (its messages' timestamps, from the first
//    EstimatedState), so a simulated vehicle may run faster than real time.
//    A call's timeout is counted on that clock; a vehicle that stops sending
//    EstimatedState for lost_after (wall) is lost.
//  - Ending: shutdown_network ends the plan (a Reference with MANDONE);
//    `surface` is a z = 0 Reference, or, when the vehicle cannot take one (in
//    ERROR, the plan failed), an Abort: surface_method() says which.
//    A plan replaced by another controller, or timed out, is reported through
//    on_fault; a silent vehicle through on_lost.
//  - Filtering: only the messages a controller needs, from the vehicle's id,
//    are decoded (the header is read first); everything else is counted.
//  - Lockstep: a vehicle that offers it (`strata vehicle --imc --lockstep`)
//    ends each cycle with a Heartbeat and waits for this link's, sent once
//    the cycle's work is done (no call issued since, no Hold alive).
//
// Threads: every method on the io_context's thread; handlers run there.
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <asio.hpp>
#include <nlohmann/json.hpp>

#include "core/result.h"
#include "imc/codec.h"
#include "protocol/message.h"
#include "protocol/rows.h"
#include "tactical/execution_link.h"

namespace strata::tactical {

struct ImcLinkOptions {
  std::string host = "127.0.0.1";
  std::uint16_t port = 6002;                // the vehicle's IMC port (DUNE's default)
  std::optional<std::uint16_t> vehicle_id;  // nullopt: the id of the first Announce from host:port
  // This link's socket, on a free port; "" (the default): the local address
  // on the route to the vehicle (127.0.0.1 for a vehicle on this machine).
  std::string bind_address;
  // This link's IMC id (a CCU's); 0 (the default): 0x4000 + its UDP port's
  // low 13 bits, so two runs on one vehicle are two controllers.
  std::uint16_t system_id = 0;
  std::uint8_t entity_id = 1;  // ... and entity, named in the plan as its controller
  std::string system_name = "strata";
  // The plan's id; "" (the default): "strata-PORT", PORT this link's own
  // UDP port, so two Strata runs on one vehicle tell their plans apart.
  std::string plan_id;
  // Wall clock: how long connect() waits for the vehicle (Announce, first
  // EstimatedState, the plan's start), and the silence after which the
  // vehicle is lost (no EstimatedState).
  std::chrono::milliseconds connect_timeout{10'000};
  std::chrono::milliseconds lost_after{5'000};
  // The vehicle's clock: the Reference stream's period (DUNE times a
  // FollowReference out after follow_timeout_s without one).
  double reference_period_s = 0.5;
  double follow_timeout_s = 10.0;
  // The asks' tolerances (the Phoenix's, config/phoenix.toml [controller]).
  double depth_tolerance_m = 0.1;
  double settle_rate_mps = 0.05;
  double surface_depth_m = 0.15;
  double heading_tolerance_deg = 3.0;
  double heading_settle_dps = 2.0;
  double heading_lead_m = 1000.0;  // `heading D` steers to a point this far along D
  // The speed toward a waypoint, a track's end or along a heading when the
  // mission set none (the Phoenix's cruise speed, config/phoenix.toml).
  double cruise_speed_mps = 0.8;
  // gps_fix is answered by the next GpsFix (DUNE: 1 Hz), or 0 when none came
  // within this much of the vehicle's time.
  double gps_wait_s = 1.5;
  // position_uncertain: NavigationUncertainty's horizontal 1-sigma above this
  // (the Phoenix's limit, config/phoenix.toml [navigation]).
  double position_limit_m = 25.0;
  // Entities whose errors the vehicle must report (DUNE reports a leak only
  // for a monitored entity): MonitorEntityState{ENABLE, these} before the
  // plan starts; "" none.
  std::string monitor_entities = "Leak Sensor - Nose";
  // start_sonar/stop_sonar: SetEntityParameters{name = this, Active = true/false}.
  std::string sonar_entity = "Sidescan";
  // Sees every message sent and decoded, as "Reference", "EstimatedState"...;
  // for traces and benchmarks. Must be quick and must not call the link.
  std::function<void(bool sent, std::string_view message)> tap;
};

// A jump of the vehicle's timestamps larger than this, either way, is a step
// of its clock, not time passing: the run's clock goes on from where it was.
inline constexpr double kMaxClockStepS = 60.0;

struct ImcVehicleInfo {
  std::string name;  // its Announce's sys_name
  std::uint16_t id = 0;
};

// What the link counted of what it did not use.
struct ImcCounts {
  std::uint64_t received = 0;       // datagrams read
  std::uint64_t used = 0;           // decoded and used
  std::uint64_t filtered = 0;       // messages a controller does not need (read no further than the header)
  std::uint64_t other_sources = 0;  // from another system, or another address
  imc::DropCounts dropped;          // undecodable, by reason
};

// "imc://HOST:PORT" or "imc://HOST:PORT/ID" (ID decimal or 0x hex: the
// vehicle's IMC id, else learnt from its Announce): the link's options.
// Errors are InvalidInput saying what is wrong with the text.
core::Result<ImcLinkOptions> parse_imc_vehicle(std::string_view text);

// "12034 received, 11890 used, 0 filtered, 3 from others, 2 dropped (2 bad_crc)".
std::string imc_summary(const ImcCounts& counts);
// The same as the mission log's mission_end "imc" object.
nlohmann::ordered_json imc_counts_json(const ImcCounts& counts);

class ImcLink final : public ExecutionLink {
 public:
  static std::shared_ptr<ImcLink> create(asio::io_context& io, ImcLinkOptions options);
  ~ImcLink() override;

  // Announces, waits for the vehicle and starts the FollowReference plan.
  void connect(std::function<void(core::Result<ImcVehicleInfo>)> done);

  protocol::RequestId send(protocol::Request request, ReplyHandler handler,
                           std::optional<std::chrono::milliseconds> timeout = std::nullopt,
                           std::optional<double> sim_timeout_s = std::nullopt) override;
  bool connected() const override { return connected_; }
  std::chrono::milliseconds default_timeout() const override { return options_.lost_after; }
  std::optional<double> sim_time_s() const override;
  void close() override;

  const ImcCounts& counts() const { return counts_; }
  std::uint16_t local_port() const { return local_port_; }
  const std::string& plan_id() const { return options_.plan_id; }
  std::uint16_t system_id() const { return options_.system_id; }
  const std::string& bind_address() const { return options_.bind_address; }
  // "reference" (a z = 0 Reference), "abort" (an Abort: the vehicle could
  // not take a Reference), or "" (no surface commanded).
  std::string_view surface_method() const { return surface_method_; }
  bool plan_running() const { return plan_running_; }
  // The vehicle offered lockstep (imc::kLockstepService): this link answers
  // each of its cycles, and sends no Heartbeat on the wall clock.
  bool lockstep() const { return lockstep_; }

 private:
  ImcLink(asio::io_context& io, ImcLinkOptions options);
  std::shared_ptr<ImcLink> self() { return std::static_pointer_cast<ImcLink>(shared_from_this()); }

  enum class Wait { NextState, Until, PlanEnd, NextGps };
  struct Pending {
    protocol::Request request;
    ReplyHandler handler;
    Wait wait = Wait::NextState;
    double sent_s = 0;                     // the vehicle's time when sent
    double until_s = 0;                    // Wait::Until
    std::optional<double> sim_deadline_s;  // timed out on the vehicle's clock
    std::optional<bool> value;             // an exec's outcome, decided when it was taken
  };
  // What this link asks the vehicle to do, in Strata's frame (x east, y north).
  struct Desired {
    std::optional<double> x_m, y_m;
    std::optional<double> speed_mps;  // set_speed's; none: cruise toward a goal, else 0
    std::optional<double> z_m;        // depth; 0 surfaces
  };
  struct VehicleStateView {
    bool have_state = false;
    double t_s = 0;  // run time of the newest EstimatedState
    double lat0 = 0, lon0 = 0;
    double x_m = 0, y_m = 0;  // Strata frame
    double depth_m = 0, alt_m = -1, vz_mps = 0, psi_deg = 0, r_dps = 0, u_mps = 0;
    std::uint8_t op_mode = 0;
    std::uint8_t error_count = 0;
    std::string error_ents, last_error;
    bool gps_valid = false;
    std::optional<double> position_sd_m;               // from NavigationUncertainty
    std::optional<double> gps_at_s;                    // the newest GpsFix's time
    std::optional<std::uint8_t> ref_state, proximity;  // the newest FollowRefState for our Reference
  };

  void start_receive();
  void on_datagram(std::size_t bytes);
  void handle(const imc::Packet& packet);
  void on_estimated_state(const imc::Packet& packet);
  void on_vehicle_state(const imc::VehicleState& m);
  void observe_clock(double timestamp);
  void on_plan_control(const imc::PlanControl& m);
  void on_plan_control_state(const imc::PlanControlState& m);
  void on_follow_ref_state(const imc::FollowRefState& m);
  void plan_started();
  void plan_ended();
  bool ready(const Pending& p) const;
  void service_pending();
  void answer(protocol::RequestId id, Pending& p);
  // Carries out an exec/ask/ood as it is sent: the effect now, the reply later.
  core::Result<void> take(Pending& p);
  // next_row with no pattern or no row left: the refusal's text.
  std::optional<std::string> row_refusal(const protocol::Request& r) const;
  bool ask(std::string_view predicate) const;
  void start_plan();
  void send_reference(bool mandone = false);
  void send_abort();
  void send_payload(bool active);
  void send_packet(const imc::Message& message, std::uint16_t dst);
  void announce();
  void arm_heartbeat();
  void arm_lost();
  // Lockstep: a check posted after each thing that may issue calls; the
  // newest one, with no Hold alive, answers the vehicle's newest cycle (its
  // Heartbeat, which ends the cycle) with a Heartbeat, once.
  void note_activity();
  void maybe_answer_cycle(std::uint64_t generation);
  void hold_released() override { note_activity(); }
  void fault(const std::string& why);
  void lost(const std::string& why);
  void fail_all(const core::Error& error);
  void emit_telemetry();
  // To the microsecond (DUNE's resolution): an epoch timestamp's double
  // carries ~0.2 us of rounding, which must not reach the log.
  double run_time(double timestamp) const { return std::round((timestamp - t0_.value_or(timestamp)) * 1e6) / 1e6; }
  std::pair<double, double> lat_lon(double x_m, double y_m) const;
  bool our_reference(const imc::Reference& r) const;

  asio::io_context& io_;
  ImcLinkOptions options_;
  asio::ip::udp::socket socket_;
  asio::ip::udp::endpoint vehicle_endpoint_;
  asio::ip::udp::endpoint sender_;
  std::vector<std::uint8_t> buffer_;
  asio::steady_timer heartbeat_timer_;
  asio::steady_timer lost_timer_;
  asio::steady_timer connect_timer_;
  std::uint16_t local_port_ = 0;
  std::function<void(core::Result<ImcVehicleInfo>)> connecting_;
  ImcVehicleInfo vehicle_;
  bool vehicle_heard_ = false;
  bool connected_ = false;
  bool closed_ = false;
  bool lost_ = false;
  bool faulted_ = false;
  bool plan_running_ = false;
  bool plan_requested_ = false;
  bool plan_confirmed_ = false;  // a PlanControlState named our plan executing
  bool mandone_sent_ = false;
  bool replaced_ = false;
  bool stopped_elsewhere_ = false;
  std::optional<std::pair<double, double>> origin_;  // lat, lon of the first EstimatedState
  std::uint64_t heartbeats_ = 0;
  bool lockstep_ = false;
  std::uint64_t activity_ = 0;
  std::optional<double> cycle_end_s_;  // lockstep: the run time of the vehicle's newest Heartbeat
  std::optional<double> answered_s_;   // ... and of the newest one answered
  std::uint64_t send_errors_ = 0;
  std::uint16_t plan_request_id_ = 0;
  std::uint16_t next_request_id_ = 1;
  std::optional<double> t0_;
  VehicleStateView state_;
  Desired desired_;
  double last_reference_s_ = -1e300;
  std::string surface_method_;
  // Local functions kept on the vehicle's clock.
  bool filter_on_ = false;
  std::optional<double> setpoint_depth_m_;
  double setpoint_timeout_s_ = 0;
  std::optional<double> timer_end_s_;
  double altitude_floor_m_ = 0;
  std::optional<double> heading_deg_;  // the last `heading`
  std::optional<std::pair<double, double>> waypoint_;
  std::optional<protocol::RowPattern> rows_;  // start_rows', kept here (protocol/rows.h)
  int next_row_ = 0;
  double telemetry_hz_ = 0;
  double next_telemetry_s_ = 0;
  protocol::RequestId next_id_ = 1;
  std::map<protocol::RequestId, Pending> pending_;
  ImcCounts counts_;
};

}  // namespace strata::tactical
