#pragma once
// `strata vehicle --imc`: the simulated Phoenix as an IMC vehicle on a UDP
// socket (docs/imc.md, "strata vehicle --imc"). ImcVehicle (imc_vehicle.h)
// is what it does; this is who hears it.
//
// Clock: the wall clock, or lockstep with its controller (options.lockstep).
// On the wall clock the simulation steps on a timer every
// cycle_s / speed wall seconds (as `strata vehicle --realtime --speed K`);
// every time in the IMC behaviour (the streams' rates, the Announce period,
// a FollowReference's timeout) is simulated time, so a run at --speed 50 is
// the same run 50 times faster. Header timestamps: kImcEpochS + simulated s.
//
// Peers: a peer is a UDP source address. Everything from an address is
// dropped unread (peek_header only) until it sends an Announce; then it is
// answered with this vehicle's Announce at once (and every 10 simulated s
// after), and every announced peer receives everything the vehicle sends.
// A peer silent for 30 s (both simulated and wall seconds: a controller
// heartbeating on either clock keeps its place) is forgotten and must
// announce again. At most max_peers are kept; an Announce past that is
// dropped (counted). Datagrams are read into one fixed buffer; a datagram
// that does not decode, a message this vehicle does not act on, a packet
// from an address that did not announce: each is counted and dropped, and
// nothing is allocated for it beyond what decoding a valid packet needs.
// While the scenario's link_loss lasts, nothing is read or sent.
//
// Threads: one; everything runs on the io_context given, which must not run
// this server's handlers after it is destroyed (destroy the server, then
// stop or destroy the io_context without running it again).
#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <asio.hpp>

#include "core/result.h"
#include "imc/codec.h"
#include "vehicle/imc_vehicle.h"
#include "vehicle/simulation.h"

namespace strata::vehicle {

// How long a lockstep vehicle waits for its controller's answer to a cycle
// (wall time; imc::kLockstepService is what it offers).
inline constexpr std::chrono::seconds kImcLockstepWait{30};

struct ImcServerOptions {
  std::string address = "127.0.0.1";
  std::uint16_t port = 0;  // 0: a free port, see ImcVehicleServer::port()
  double speed = 1.0;      // simulated seconds per wall second
  std::uint16_t imc_id = 0x2C01;
  std::string system_name = "phoenix-sim";
  std::size_t max_peers = 16;
  // Where the vehicle's own log lines go; with trace, every packet received
  // and sent too (except the streams, which would drown the rest).
  std::function<void(const std::string&)> log;
  bool trace = false;
  // Lockstep (docs/imc.md, "Lockstep"): after each cycle the simulation waits
  // for its controller to say it has done with it (a Heartbeat stamped with
  // that cycle's time) instead of for the wall clock, as fast as
  // the controller goes and the same whatever the machine's load. Offered in
  // the Announce's services as imc::kLockstepService; a controller that does
  // not answer gets a cycle each lockstep_wait of wall time.
  bool lockstep = false;
  std::chrono::milliseconds lockstep_wait = kImcLockstepWait;
};

// Contact timeouts and periods (simulated seconds unless said).
inline constexpr double kImcPeerSilenceS = 30.0;
inline constexpr double kImcAnnouncePeriodS = 10.0;

struct ImcServerCounts {
  std::uint64_t datagrams = 0;             // read from the socket
  std::uint64_t accepted = 0;              // decoded from an announced peer, given to the vehicle
  imc::DropCounts dropped;                 // did not decode (Filtered: from an address that did not announce)
  std::uint64_t peers_refused = 0;         // Announces past max_peers
  std::uint64_t peers_forgotten = 0;       // silent for kImcPeerSilenceS
  std::uint64_t not_acted_on = 0;          // decoded, from a peer, a message the vehicle does not act on
  std::uint64_t lost_in_link_loss = 0;     // read while the scenario's link_loss lasts
  std::uint64_t sent = 0;                  // datagrams sent (one per peer per message)
  std::uint64_t send_failed = 0;           // the socket refused one (buffer full, peer gone)
  std::uint64_t lockstep_waits_ended = 0;  // lockstep: cycles that came after lockstep_wait, unanswered
};

class ImcVehicleServer {
 public:
  ImcVehicleServer(asio::io_context& io, Simulation& sim, ImcServerOptions options);
  ~ImcVehicleServer();
  ImcVehicleServer(const ImcVehicleServer&) = delete;
  ImcVehicleServer& operator=(const ImcVehicleServer&) = delete;

  // Binds the UDP socket and starts the clock; ErrorCode::Io if the address
  // is taken, InvalidInput if it is not an address.
  core::Result<void> start();
  void stop();
  std::uint16_t port() const { return port_; }
  std::size_t peer_count() const { return peers_.size(); }
  const ImcServerCounts& counts() const { return counts_; }
  const ImcVehicle& vehicle() const { return vehicle_; }

 private:
  struct Peer {
    asio::ip::udp::endpoint endpoint;
    std::uint16_t imc_id = 0;
    double last_heard_s = 0.0;  // simulated
    std::chrono::steady_clock::time_point last_heard_wall;
  };

  void receive();
  void on_datagram(std::size_t n);
  Peer* find_peer(const asio::ip::udp::endpoint& from);
  void on_announce(const imc::Header& h);
  void tick();
  void cycle();
  // Lockstep: a Heartbeat stamped with the cycle waited for, from the
  // running plan's controller (any peer when no plan runs), ends the wait.
  void on_heartbeat(const imc::Header& h);
  // Lockstep: the next cycle now (an answer, a new controller, the first one).
  void cycle_now();
  void forget_silent_peers();
  imc::Announce announce() const;
  // Encodes m (from this vehicle's id, entity 0) and sends it to every peer
  // (to_one: only that one).
  void send(const imc::Message& m, std::uint16_t dst, std::uint8_t dst_ent, const Peer* to_one = nullptr);
  void flush_outbox();
  void log(const std::string& line) const;

  asio::io_context& io_;
  Simulation& sim_;
  ImcServerOptions options_;
  ImcVehicle vehicle_;
  asio::ip::udp::socket socket_;
  asio::steady_timer tick_timer_;
  std::uint16_t port_ = 0;
  bool stopped_ = false;
  bool clock_started_ = false;      // at the first peer's Announce
  bool stepped_ = false;            // a cycle has run (lockstep waits only after one)
  std::optional<double> awaiting_;  // lockstep: the timestamp of the cycle waiting for its answer
  std::uint64_t wait_ = 0;          // lockstep: the wait's number (a timer's handler already queued is stale)
  std::array<std::uint8_t, 65536> buffer_{};
  asio::ip::udp::endpoint from_;
  std::vector<Peer> peers_;
  double next_announce_s_ = 0.0;
  ImcServerCounts counts_;
};

}  // namespace strata::vehicle
