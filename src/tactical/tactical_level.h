#pragma once
// The Tactical level as the Strategic level sees it (paper §2.1): vehicle
// primitives called by name, each answered 1 or 0 (TRUE/FALSE in response to
// commands and queries). It renders each call from the catalogue, serves
// next_setpt_data from the mission data cursor, sends the script message over
// the ExecutionLink (VehicleLink or ImcLink), prints and logs REPORT, and writes every request, reply,
// telemetry sample and vehicle event to the mission log.
//
// Both Strategic levels (the CORAL Engine and the PROLOG executor) call this
// one interface, so they issue the same primitive calls.
//
// Outcomes it delivers itself (REPORT's, local errors) are posted to the
// io_context under an ExecutionLink::Hold, so a lockstep link does not advance
// the vehicle before the caller has answered them.
//
// Threads: one; call on the io_context's thread. Handlers run there.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <asio.hpp>

#include "core/call_verb.h"
#include "core/result.h"
#include "tactical/call_error.h"
#include "tactical/catalogue.h"
#include "tactical/mission_data.h"
#include "tactical/mission_log.h"
#include "tactical/render.h"
#include "tactical/execution_link.h"
#include "tactical/value.h"

namespace strata::tactical {

struct CallOutcome {
  bool value = false;       // exec/ood: the function executed; ask: the predicate
  double sim_time_s = 0.0;  // the vehicle's time at the reply
};

// A call's outcome: its answer, or why it has none (call_error.h).
using CallResult = core::Result<CallOutcome, CallError>;
using CallHandler = std::function<void(CallResult)>;

// What one call looked like, for traces (strata compare) and tests.
struct CallRecord {
  std::string primitive;
  std::optional<core::CallVerb> verb;  // the primitive's kind; nullopt when no primitive has the name
  std::string message;                 // "exec sleep 1"; for report, the text
  std::optional<bool> value;           // the answer; nullopt when the call failed
  std::optional<CallError> error;      // set when the call failed
  double sim_time_s = 0.0;             // the vehicle's time when the call completed
  // An exec or ood answered 0: the last event the vehicle sent while the
  // call was in flight ("exec submerge failed: depth filter is off"), its
  // reason as far as the protocol can tell (events name no request; with
  // calls in flight together it may be another's). "" if none came.
  std::string vehicle_said;
  // A guard's own poll (docs/language.md, "guard"): the guard's name; "" for
  // a call of the mission itself.
  std::string guard;
};

class TacticalLevel {
 public:
  // Outcomes are delivered on io. link may be null for a run that only
  // reports (tests). cursor and log may be null (no mission data; no log).
  // All must outlive this object.
  TacticalLevel(asio::io_context& io, const Catalogue& catalogue, std::shared_ptr<ExecutionLink> link,
                DataCursor* cursor, MissionLog* log);

  // On the wall clock at speed K, a call that may take T simulated seconds
  // takes T/K wall seconds: set 1/K here so reply timeouts stretch to match.
  // Lockstep and real time: 1 (the default).
  void set_wall_seconds_per_sim_second(double scale) { wall_per_sim_ = scale; }

  // Calls primitive `name` with args. done is called exactly once, never
  // before call() returns: with the outcome, or with a CallError whose kind
  // says why (BadCall: unknown primitive, bad arguments, no mission data or
  // past the last setpoint; Refused: the vehicle's `err`, with its code;
  // TimedOut; LinkLost; BadReply). REPORT answers 1 at once.
  // `guard` names the guard whose poll this is ("": the mission's own call);
  // the call's record carries it.
  void call(std::string_view name, std::vector<Value> args, CallHandler done, std::string_view guard = {});

  // Where REPORT text goes besides the log (the operator console).
  void on_report(std::function<void(const std::string&, double sim_time_s)> f) { on_report_ = std::move(f); }
  // Telemetry samples and vehicle events, after they are logged.
  void on_telemetry(std::function<void(const protocol::Telemetry&)> f) { on_telemetry_ = std::move(f); }
  void on_vehicle_event(std::function<void(const protocol::Event&)> f) { on_event_ = std::move(f); }
  // Every call as it completes, in completion order.
  void on_call(std::function<void(const CallRecord&)> f) { on_call_ = std::move(f); }

  // The vehicle's time as last heard (replies, telemetry, events).
  double sim_time_s() const { return sim_time_s_; }
  // The vehicle's time in the last line heard from it (a reply, telemetry,
  // an event); sim_time_s() may be later, when a call timed out in
  // simulated time while the vehicle was silent.
  double last_heard_s() const { return last_heard_s_; }
  std::uint64_t calls() const { return calls_; }
  std::size_t in_flight() const { return in_flight_; }

 private:
  void finish(const CallRecord& record, CallHandler& done, CallResult outcome);

  asio::io_context& io_;
  const Catalogue& catalogue_;
  std::shared_ptr<ExecutionLink> link_;
  DataCursor* cursor_;
  MissionLog* log_;
  std::function<void(const std::string&, double)> on_report_;
  std::function<void(const CallRecord&)> on_call_;
  std::function<void(const protocol::Telemetry&)> on_telemetry_;
  std::function<void(const protocol::Event&)> on_event_;
  double sim_time_s_ = 0.0;
  double last_heard_s_ = 0.0;
  double wall_per_sim_ = 1.0;
  std::uint64_t calls_ = 0;
  std::size_t in_flight_ = 0;
  std::uint64_t next_report_id_ = 1;
  // Vehicle events heard so far, and the last one's text (CallRecord::vehicle_said).
  std::uint64_t events_heard_ = 0;
  std::string last_event_;
};

// The protocol verb a call goes out with: exec, ask, ood; nullopt for
// report, which is never sent.
std::optional<protocol::Verb> wire_verb(core::CallVerb verb);

// A protocol request for a rendered call (verb, name and typed arguments).
// call.to_vehicle() must hold.
protocol::Request to_request(const RenderedCall& call);

// The fields a telemetry line gives the mission log's "telemetry" record, in
// its order: depth_m, filtered_depth_m, rate_mps, thrust_n, setpoint_m,
// heading_deg, then, when the vehicle sends them (open water: docs/protocol.md),
// x_m, y_m (estimated), true_x_m, true_y_m, position_sd_m, speed_mps,
// altitude_m. A field the line lacks, or a non-number, is left out, so a
// tank run's log reads as before.
nlohmann::ordered_json telemetry_log_fields(const protocol::Telemetry& t);
// The whole telemetry line of the log, {"event":"telemetry","sim_time":...}
// and those fields, written without building a JSON value.
LogLine telemetry_log_line(const protocol::Telemetry& t);

}  // namespace strata::tactical
