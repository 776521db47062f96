#pragma once
// `strata vehicle`: the Execution level behind a TCP socket, speaking
// protocol 1 or 2 (the client's hello chooses) to one controlling client at
// a time.
//
// Clocks (docs/protocol.md §8):
//  - Lockstep: simulated time moves only when the client lets it. Every
//    exec/ask/ood costs at least one cycle (0.1 s) before it is answered;
//    `sleep N` costs N seconds. A request's effect happens when it arrives;
//    its reply comes at the end of the cycle it is due (an ask answers with
//    the state then).
//      Protocol 2: requests wait until the client sends `advance` (it has
//      issued everything for the current instant). Then the vehicle steps
//      cycle by cycle, every waiting request together, until at least one is
//      due; it answers every request due at that cycle, in id order, then
//      `ok` to the advance, and waits for the next one. Requests in flight at
//      the same time share simulated time, as on the wall clock.
//      Protocol 1: each request advances time itself when it arrives, so
//      requests are served one after the other in arrival order.
//    Either way a run is a pure function of the lines received.
//  - Wall: the simulation steps on a timer at cycle_s / speed wall seconds;
//    requests are answered at once, `sleep N` after N simulated seconds;
//    `advance` is answered at once and changes nothing.
//
// Watchdog: when the controlling link drops, or stays silent for watchdog_s
// (simulated seconds on the wall clock; in lockstep, wall seconds
// (ServerOptions::lockstep_silence_s, or never) counted from the last line
// received or reply sent), the vehicle surfaces by itself
// and says why in an event; requests still waiting for their cycle are
// answered `err ID not_ready`. In lockstep it then runs on its own until it
// is at the surface. A protocol-2 client that holds requests without sending
// `advance` is silent: nothing moves until it speaks.
//
// Hello: a client controls the vehicle from the hello this vehicle accepts,
// not from its connection. Until then it waits beside the others that
// connected (at most kMaxWaitingClients; one more is refused `busy`), is
// answered only `err ID not_ready` ("say hello first") and hears nothing
// else (no heartbeat, no telemetry); the first whose hello is accepted gets
// the vehicle, and the others still waiting are refused `busy` and closed.
// So a client that connects and says nothing never blocks a real
// controller. One that has not said an accepted hello within
// hello_timeout_s (wall seconds from its connection) is sent
// `err 0 not_ready` saying why and closed. A hello naming a version this
// vehicle does not speak is answered `err ID bad_argument` naming the
// versions it speaks; the client stays and may say hello again (within the
// timeout). While a controller holds the vehicle, a new client is refused
// `busy` at once.
//
// A scenario's link_loss makes the link silent: from its time on, the
// vehicle neither reads nor answers the controller (lines are dropped, as a
// cut cable would), and the watchdog does the rest. In lockstep the clock is
// the simulator's, not the vehicle's: an `advance ID UNTIL_S` still moves
// simulated time (to UNTIL_S) and is answered `ok ID T`, so a client's reply
// timeouts run out in simulated time, and the watchdog trips watchdog_s
// simulated seconds into the silence.
//
// Threads: one; everything runs on the io_context given, which must not run
// this server's handlers after it is destroyed (destroy the server, then
// stop or destroy the io_context without running it again).
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <asio.hpp>

#include "protocol/line_connection.h"
#include "protocol/message.h"
#include "vehicle/simulation.h"
#include "vehicle/sonar_server.h"
#include "vehicle/telemetry_sampler.h"

namespace strata::vehicle {

// Clients connected at once without an accepted hello; one more is refused.
inline constexpr std::size_t kMaxWaitingClients = 8;

struct ServerOptions {
  std::string address = "127.0.0.1";
  std::uint16_t port = 0;  // 0: a free port, see VehicleServer::port()
  protocol::ClockMode clock = protocol::ClockMode::Lockstep;
  double speed = 1.0;  // wall clock: simulated seconds per wall second
  std::string vehicle_name = "phoenix-sim";
  // Where the vehicle's own log lines go ("12.3 s: watchdog: ..."), and
  // every line received and sent when trace is on.
  std::function<void(const std::string&)> log;
  bool trace = false;
  // Lockstep, after a watchdog trip: simulated seconds to run on alone.
  double autonomous_run_s = 120.0;
  // Wall seconds a new controller has to say hello before it is dropped
  // (so that a client that connects and says nothing cannot hold the
  // vehicle); <= 0: no limit.
  double hello_timeout_s = 5.0;
  // Lockstep: wall seconds of silence after which the watchdog trips (a
  // controller hung with its connection open; the simulation waits for it
  // otherwise). nullopt: the vehicle's watchdog_s. <= 0: never, for a
  // controller in this process (strata run's embedded vehicle), whose end
  // closes the link: a run is then a pure function of its inputs, whatever
  // the machine's load or a rule blocking for a while.
  std::optional<double> lockstep_silence_s;
  // The sonar socket (docs/protocol.md §10), on the same address.
  bool sonar = true;
  std::uint16_t sonar_port = 0;  // 0: a free port, see VehicleServer::sonar_port()
};

// Lockstep: the most simulated time one bounded advance moves (a client's
// bound past it is answered at this point, and the client advances again).
inline constexpr double kMaxAdvanceSpanS = 3600.0;

class VehicleServer {
 public:
  VehicleServer(asio::io_context& io, Simulation& sim, ServerOptions options);
  ~VehicleServer();

  // Binds and listens; fails with ErrorCode::Io if the address is taken.
  core::Result<void> start();
  // Started with no listening socket: its one client is the other end of a
  // connected pair of local sockets (the embedded vehicle of a run, in the
  // same process: no TCP stack between the two levels). port() is 0; the
  // sonar still listens on TCP.
  core::Result<void> start_paired(protocol::LineConnection::Socket client);
  void stop();
  std::uint16_t port() const { return port_; }
  // 0 without a sonar socket.
  std::uint16_t sonar_port() const { return sonar_ ? sonar_->port() : 0; }
  const SonarServer* sonar() const { return sonar_.get(); }
  std::size_t clients_refused() const { return refused_; }
  // The controller is gone, told by the one who knows first (an embedded
  // vehicle's own run, which closed its end of the link): as when the
  // server reads the end of the link, at the same simulated time, but now,
  // so that when_settled() waits for the watchdog's surfacing it causes.
  // Nothing when there is no controller.
  void controller_gone();
  // Calls f (on the io_context) once the vehicle is not running on its own:
  // at once, unless a watchdog trip has it surfacing by itself, in which
  // case when that is over: at the surface, or autonomous_run_s later (in
  // lockstep it runs alone; on the wall clock it moves with its ticks), or
  // the server stops.
  void when_settled(std::function<void()> f);

 private:
  void accept();
  // The sonar and, on the wall clock, the clock: the rest of a start.
  core::Result<void> start_running();
  // A connected client: waits for its hello, or is refused.
  void admit(protocol::LineConnection::Socket socket);
  void on_request(protocol::LineConnection& c, const protocol::Request& r);
  void refuse(protocol::LineConnection& c, const std::string& why);
  // A waiting client's line: its hello, or `not_ready`.
  void on_waiting_line(const std::shared_ptr<protocol::LineConnection>& c, const protocol::Frame& frame);
  // The client whose hello was accepted becomes the controller.
  void take_control(const std::shared_ptr<protocol::LineConnection>& c, const protocol::Request& hello);
  std::shared_ptr<protocol::LineConnection> waiting_client(const protocol::LineConnection& c) const;
  void drop_waiting(const protocol::LineConnection& c);
  void on_call(const protocol::Request& r);
  void advance(std::optional<protocol::RequestId> advance_id, std::optional<double> until_s = std::nullopt);
  // Whether a line is the lockstep clock (a bounded advance), which a lost
  // link still carries.
  bool is_clock_line(const protocol::Frame& frame) const;
  // Lockstep: the watchdog trips watchdog_s simulated seconds into a silence
  // the scenario made.
  void watch_lost_link();
  void reply_due();
  bool in_flight(protocol::RequestId id) const;
  void arm_hello_timeout(const std::shared_ptr<protocol::LineConnection>& c, asio::steady_timer& timer);
  void on_line(protocol::LineConnection& c, const protocol::Frame& frame);
  void on_closed(protocol::LineConnection& c, const protocol::CloseReason& why);
  void send(const protocol::VehicleMessage& m);
  // The end of a bounded advance: sent whether or not the link is lost.
  void send_clock(const protocol::Ok& ok);
  // Writes a line (with its newline) to c, traced when trace is on.
  void write(protocol::LineConnection& c, std::string line);
  void step_one();
  void after_step();
  void flush_events();
  void flush_pings();
  void reply_later(protocol::RequestId id, double until_s);
  // Lockstep: the silence counts again from now. The timer is not re-armed
  // for each line (a syscall and a cancelled wait each time): one wait is
  // kept, and when it ends early it waits again for the newest deadline.
  void arm_silence_watchdog();
  void wait_for_silence();
  void cancel_silence_watchdog();
  void trip(const std::string& reason);
  void run_alone(std::optional<double> trip_at_s);
  void run_alone_batch();
  void settled();
  // Wall clock: calls the when_settled waiters once the vehicle is at the
  // surface after a trip, or wall_settle_until_s_ has come.
  void check_wall_settled();
  void tick();
  void log(const std::string& line);

  asio::io_context& io_;
  Simulation& sim_;
  ServerOptions options_;
  asio::ip::tcp::acceptor acceptor_;
  asio::steady_timer tick_timer_;
  asio::steady_timer silence_timer_;
  std::chrono::steady_clock::time_point silence_deadline_{};
  bool silence_waiting_ = false;          // a wait of silence_timer_ is pending
  std::uint64_t silence_generation_ = 0;  // a cancelled wait's handler is stale
  // Connected, no accepted hello yet: each with its hello timer.
  struct WaitingClient {
    std::shared_ptr<protocol::LineConnection> conn;
    std::unique_ptr<asio::steady_timer> hello_timer;
  };
  std::vector<WaitingClient> waiting_clients_;
  std::shared_ptr<protocol::LineConnection> controller_;  // said an accepted hello
  std::unique_ptr<SonarServer> sonar_;
  bool sonar_was_on_ = false;
  std::uint16_t port_ = 0;
  std::size_t refused_ = 0;
  bool stopped_ = false;
  bool hello_done_ = false;
  std::optional<double> wall_settle_until_s_;  // wall clock: waiting for the vehicle to surface by itself
  int session_version_ = 0;                    // the controller's protocol version, once it said hello
  bool running_alone_ = false;
  double alone_until_s_ = 0.0;
  std::optional<double> alone_trip_at_s_;
  std::optional<double> silent_since_s_;           // lockstep: when the scenario's silence began
  bool surfaced_in_silence_ = false;               // ... and the vehicle's log said it is up
  std::optional<protocol::Request> held_advance_;  // a bounded advance that came while running alone
  std::vector<std::function<void()>> settled_waiters_;
  TelemetrySampler telemetry_;
  double last_rx_s_ = 0.0;  // sim time of the last line from the controller (wall mode)
  double next_heartbeat_s_ = 1.0;
  struct Deferred {
    protocol::RequestId id;
    double until_s;
  };
  std::vector<Deferred> deferred_;  // wall clock: sleeps waiting for their time
  // Lockstep: requests taken (their effect done) and waiting for their cycle.
  struct Waiting {
    protocol::Request request;
    bool value = false;           // exec/ood: whether it executed
    std::uint64_t due_cycle = 0;  // answered at the end of this cycle
  };
  std::vector<Waiting> waiting_;
};

}  // namespace strata::vehicle
