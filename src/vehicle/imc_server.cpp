#include "vehicle/imc_server.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "vehicle/cycle_timer.h"

namespace strata::vehicle {
namespace {

using Clock = std::chrono::steady_clock;

// The streams, left out of the trace (they would drown the rest).
bool is_stream(std::uint16_t id) {
  return id == imc::EstimatedState::kId || id == imc::VehicleState::kId || id == imc::PlanControlState::kId ||
         id == imc::GpsFix::kId || id == imc::Heartbeat::kId || id == imc::NavigationUncertainty::kId;
}

std::string endpoint_text(const asio::ip::udp::endpoint& e) {
  return fmt::format("{}:{}", e.address().to_string(), e.port());
}

}  // namespace

ImcVehicleServer::ImcVehicleServer(asio::io_context& io, Simulation& sim, ImcServerOptions options)
    : io_(io),
      sim_(sim),
      options_(std::move(options)),
      vehicle_(sim, ImcVehicleOptions{options_.imc_id, kImcOriginLatRad, kImcOriginLonRad, options_.log}),
      socket_(io),
      tick_timer_(io) {
  peers_.reserve(options_.max_peers);
}

ImcVehicleServer::~ImcVehicleServer() { stop(); }

void ImcVehicleServer::log(const std::string& line) const {
  if (options_.log) options_.log(line);
}

core::Result<void> ImcVehicleServer::start() {
  asio::error_code ec;
  auto address = asio::ip::make_address(options_.address, ec);
  if (ec) {
    return core::make_error(core::ErrorCode::InvalidInput, fmt::format("'{}' is not an IP address", options_.address));
  }
  asio::ip::udp::endpoint endpoint(address, options_.port);
  socket_.open(endpoint.protocol(), ec);
  if (!ec) socket_.bind(endpoint, ec);
  // A full send buffer drops the datagram (counted) instead of blocking the loop.
  if (!ec) socket_.non_blocking(true, ec);
  if (ec) {
    return core::make_error(core::ErrorCode::Io,
                            fmt::format("cannot bind udp {}:{}: {}", options_.address, options_.port, ec.message()));
  }
  port_ = socket_.local_endpoint().port();
  receive();  // the clock starts with the first peer (on_announce)
  return {};
}

void ImcVehicleServer::stop() {
  if (stopped_) return;
  stopped_ = true;
  asio::error_code ignored;
  tick_timer_.cancel();
  socket_.close(ignored);
}

// ---- receiving -------------------------------------------------------------------

void ImcVehicleServer::receive() {
  socket_.async_receive_from(asio::buffer(buffer_), from_, [this](const asio::error_code& e, std::size_t n) {
    if (stopped_ || e == asio::error::operation_aborted) return;
    // Other errors (an ICMP "port unreachable" from a peer that went away,
    // reported on the next read) concern one datagram: read on.
    if (!e) on_datagram(n);
    receive();
  });
}

ImcVehicleServer::Peer* ImcVehicleServer::find_peer(const asio::ip::udp::endpoint& from) {
  for (auto& p : peers_) {
    if (p.endpoint == from) return &p;
  }
  return nullptr;
}

void ImcVehicleServer::on_datagram(std::size_t n) {
  ++counts_.datagrams;
  if (sim_.link_lost()) {
    ++counts_.lost_in_link_loss;
    return;
  }
  const std::span<const std::uint8_t> datagram(buffer_.data(), n);
  Peer* peer = find_peer(from_);
  if (!peer) {
    // Unheard until it announces: only its header is read.
    const auto header = imc::peek_header(datagram);
    if (!header) {
      counts_.dropped.add(n < imc::kHeaderBytes + imc::kFooterBytes ? imc::Drop::Truncated : imc::Drop::BadSync);
      return;
    }
    if (header->mgid != imc::Announce::kId) {
      counts_.dropped.add(imc::Drop::Filtered);
      return;
    }
  }
  auto decoded = imc::decode(datagram);
  if (const auto* drop = std::get_if<imc::Drop>(&decoded)) {
    counts_.dropped.add(*drop);
    return;
  }
  const auto& packet = std::get<imc::Packet>(decoded);
  const std::uint16_t id = imc::id_of(packet.message);
  if (options_.trace && id != imc::Heartbeat::kId) {
    log(fmt::format("< {} from 0x{:04X} ({})", imc::name_of(id), packet.header.src, endpoint_text(from_)));
  }
  if (id == imc::Announce::kId) {
    on_announce(packet.header);
    return;
  }
  peer->last_heard_s = sim_.time_s();
  peer->last_heard_wall = Clock::now();
  if (id == imc::Heartbeat::kId) {
    on_heartbeat(packet.header);
    return;
  }
  if (id == imc::PlanControl::kId || id == imc::Reference::kId || id == imc::Abort::kId ||
      id == imc::SetEntityParameters::kId) {
    ++counts_.accepted;
    vehicle_.receive(packet.header, packet.message);
    flush_outbox();  // replies at once, not at the next cycle
    return;
  }
  ++counts_.not_acted_on;
}

void ImcVehicleServer::on_announce(const imc::Header& h) {
  if (Peer* p = find_peer(from_)) {
    p->imc_id = h.src;
    p->last_heard_s = sim_.time_s();
    p->last_heard_wall = Clock::now();
    return;
  }
  if (peers_.size() >= options_.max_peers) {
    // Logged on the first and then every 100th, so that a flood cannot fill the log.
    if (counts_.peers_refused++ % 100 == 0) {
      log(fmt::format("{:.1f} s: Announce from {} refused: {} peers already ({} refused so far)", sim_.time_s(),
                      endpoint_text(from_), options_.max_peers, counts_.peers_refused));
    }
    return;
  }
  peers_.push_back(Peer{from_, h.src, sim_.time_s(), Clock::now()});
  log(fmt::format("{:.1f} s: peer 0x{:04X} at {} announced", sim_.time_s(), h.src, endpoint_text(from_)));
  send(announce(), h.src, imc::kAnyEntity, &peers_.back());
  if (!clock_started_) {
    // The simulation, and the scenario's fault times with it, start when the
    // first controller is heard: a vehicle started before its controller
    // does not live through its faults alone (at --speed 100, a second of
    // wall time is 100 s of the scenario).
    clock_started_ = true;
    if (options_.lockstep) {
      cycle_now();  // not a wall-clock cycle's wait first
    } else {
      tick();
    }
  } else if (awaiting_) {
    // Lockstep: a new controller answers cycles it has seen; it starts from
    // one of its own, not after the wait for a controller that may be gone
    // (the run before it).
    cycle_now();
  }
}

// ---- the clock ---------------------------------------------------------------------

void ImcVehicleServer::tick() {
  // Lockstep: the next cycle when a controller has done with this one (its
  // Heartbeat ends the wait early), else after lockstep_wait. With the
  // link lost (nothing is heard) or no peer, on the wall clock.
  if (options_.lockstep && stepped_ && !peers_.empty() && !sim_.link_lost()) {
    awaiting_ = vehicle_.timestamp();
    const std::uint64_t wait = ++wait_;
    tick_timer_.expires_after(options_.lockstep_wait);
    tick_timer_.async_wait([this, wait](const asio::error_code& e) {
      // An expiry already queued when an answer came cannot be cancelled:
      // it is stale, and the answer's cycle runs instead.
      if (e || stopped_ || wait != wait_ || !awaiting_) return;
      ++counts_.lockstep_waits_ended;
      awaiting_.reset();
      cycle();
      tick();
    });
    return;
  }
  awaiting_.reset();
  // Out of a lockstep wait, the wall clock's cycle counts from now.
  if (options_.lockstep) tick_timer_.expires_at(asio::steady_timer::time_point{});
  // Two cycles behind at the most: what waits in the socket is read
  // between cycles, at the simulated time it came (cycle_timer.h).
  arm_next_cycle(tick_timer_, sim_.params().cycle_s, options_.speed, 2);
  tick_timer_.async_wait([this](const asio::error_code& e) {
    if (e || stopped_) return;
    cycle();
    tick();
  });
}

void ImcVehicleServer::on_heartbeat(const imc::Header& h) {
  if (!awaiting_) return;
  // The cycle's own stamp, to a millisecond (the controller's stamp is the
  // vehicle's, carried through its own arithmetic; a cycle is 100 ms): not
  // a console's Heartbeat on the wall clock, nor a stamp that is no time.
  if (!std::isfinite(h.timestamp) || std::abs(h.timestamp - *awaiting_) > 1e-3) return;
  // While a plan runs, its controller paces the vehicle, not another peer.
  if (const auto controller = vehicle_.plan_controller();
      controller && *controller != imc::kNullId && *controller != h.src) {
    return;
  }
  cycle_now();
}

void ImcVehicleServer::cycle_now() {
  awaiting_.reset();
  ++wait_;
  // The waiting timer's handler sees operation_aborted, or (already
  // queued) a wait number gone by, and does nothing; the cycle runs after
  // what this datagram's reading queued.
  tick_timer_.cancel();
  asio::post(io_, [this] {
    if (stopped_) return;
    cycle();
    tick();
  });
}

void ImcVehicleServer::cycle() {
  stepped_ = true;
  vehicle_.step();
  forget_silent_peers();
  if (sim_.time_s() + 1e-9 >= next_announce_s_) {
    if (next_announce_s_ > 0) send(announce(), imc::kNullId, imc::kAnyEntity);
    next_announce_s_ += kImcAnnouncePeriodS;
  }
  flush_outbox();
  // Lockstep: a Heartbeat ends every cycle, after its streams; the
  // controller answers it when it has done with them.
  if (options_.lockstep) send(imc::Heartbeat{}, imc::kNullId, imc::kAnyEntity);
}

void ImcVehicleServer::forget_silent_peers() {
  const auto now_wall = Clock::now();
  const auto wall_limit = std::chrono::duration<double>(kImcPeerSilenceS);
  std::erase_if(peers_, [&](const Peer& p) {
    const bool silent = sim_.time_s() - p.last_heard_s > kImcPeerSilenceS && now_wall - p.last_heard_wall > wall_limit;
    if (silent) {
      ++counts_.peers_forgotten;
      log(fmt::format("{:.1f} s: peer 0x{:04X} at {} silent for {} s: forgotten", sim_.time_s(), p.imc_id,
                      endpoint_text(p.endpoint), kImcPeerSilenceS));
    }
    return silent;
  });
}

// ---- sending -------------------------------------------------------------------------

imc::Announce ImcVehicleServer::announce() const {
  imc::Announce a;
  a.sys_name = options_.system_name;
  a.sys_type = imc::Announce::kSysTypeUuv;
  a.owner = imc::kNullId;
  const auto [lat, lon] = vehicle_.to_lat_lon(sim_.navigator().x_m(), sim_.navigator().y_m());
  a.lat = lat;
  a.lon = lon;
  a.services = fmt::format("imc+udp://{}:{}/", options_.address, port_);
  if (options_.lockstep) a.services += fmt::format(";{}", imc::kLockstepService);
  return a;
}

void ImcVehicleServer::flush_outbox() {
  for (const auto& out : vehicle_.take_outbox()) send(out.message, out.dst, out.dst_ent);
}

void ImcVehicleServer::send(const imc::Message& m, std::uint16_t dst, std::uint8_t dst_ent, const Peer* to_one) {
  if (sim_.link_lost() || peers_.empty()) return;  // the link is silent both ways
  imc::Packet packet;
  packet.header.timestamp = vehicle_.timestamp();
  packet.header.src = options_.imc_id;
  packet.header.src_ent = 0;
  packet.header.dst = dst;
  packet.header.dst_ent = dst_ent;
  packet.message = m;
  auto bytes = imc::encode(packet);
  if (!bytes) {
    log(fmt::format("cannot encode {}: {}", imc::name_of(imc::id_of(m)), bytes.error().message));
    return;
  }
  if (options_.trace && !is_stream(imc::id_of(m))) {
    log(fmt::format("> {} to 0x{:04X}", imc::name_of(imc::id_of(m)), dst));
  }
  const auto send_one = [&](const Peer& p) {
    asio::error_code ec;
    socket_.send_to(asio::buffer(bytes.value()), p.endpoint, 0, ec);
    ++(ec ? counts_.send_failed : counts_.sent);
  };
  if (to_one) {
    send_one(*to_one);
    return;
  }
  for (const auto& p : peers_) send_one(p);
}

}  // namespace strata::vehicle
