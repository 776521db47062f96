#pragma once
// Test support: a vehicle server and its simulation on one io_context, and a
// way to run the loop until something happened (bounded, so a broken test
// fails instead of hanging).
#include <array>
#include <atomic>
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <asio.hpp>
#include <gtest/gtest.h>

#include "protocol/codec.h"
#include "tactical/vehicle_link.h"
#include "vehicle/server.h"

namespace strata::tactical::testing {

using namespace std::chrono_literals;
using protocol::VehicleMessage;

// Runs io until done() or a time bound passes; the bound only keeps a broken
// test from hanging, it asserts nothing about speed.
template <typename Pred>
bool run_until(asio::io_context& io, Pred done, std::chrono::milliseconds bound = 5000ms) {
  auto deadline = std::chrono::steady_clock::now() + bound;
  io.restart();
  while (!done() && std::chrono::steady_clock::now() < deadline) {
    if (io.stopped()) io.restart();
    io.run_one_for(10ms);  // one handler at a time, so done() is seen at once
  }
  return done();
}

// A link on io to the vehicle at options.port, connected: its welcome is
// checked (a test failure when it does not come or is a refusal).
inline std::shared_ptr<VehicleLink> connect_link(asio::io_context& io, const LinkOptions& options) {
  auto link = VehicleLink::create(io, options);
  std::optional<core::Result<protocol::Welcome>> welcome;
  link->connect([&](core::Result<protocol::Welcome> r) { welcome = std::move(r); });
  EXPECT_TRUE(run_until(io, [&] { return welcome.has_value(); }));
  EXPECT_TRUE(welcome && welcome->ok()) << (welcome && !welcome->ok() ? welcome->error().message : "");
  return link;
}

struct Rig {
  // configure, if set, sees the server's options last (hello timeout, ...).
  explicit Rig(vehicle::Scenario scenario = vehicle::Scenario::nominal(),
               protocol::ClockMode clock = protocol::ClockMode::Lockstep,
               vehicle::VehicleParams params = vehicle::default_params(),
               const std::function<void(vehicle::ServerOptions&)>& configure = nullptr)
      : sim(params, std::move(scenario)) {
    vehicle::ServerOptions so;
    so.clock = clock;
    so.speed = 20.0;
    so.log = [this](const std::string& line) { vehicle_log.push_back(line); };
    if (configure) configure(so);
    server = std::make_unique<vehicle::VehicleServer>(io, sim, so);
    EXPECT_TRUE(server->start().ok());
  }

  std::shared_ptr<VehicleLink> connect(LinkOptions options = {}) {
    options.port = server->port();
    return connect_link(io, options);
  }

  core::Result<VehicleMessage> call(VehicleLink& link, protocol::Request r,
                                    std::optional<std::chrono::milliseconds> timeout = std::nullopt) {
    std::optional<core::Result<VehicleMessage>> reply;
    link.send(
        std::move(r), [&](core::Result<VehicleMessage> m) { reply = std::move(m); }, timeout);
    EXPECT_TRUE(run_until(io, [&] { return reply.has_value(); }));
    if (!reply) return core::make_error(core::ErrorCode::Internal, "no reply in the test's bound");
    return std::move(*reply);
  }

  bool ask(VehicleLink& link, const std::string& predicate) {
    auto r = call(link, protocol::make_ask(0, predicate));
    EXPECT_TRUE(r.ok()) << r.error().message;
    return r.ok() && std::get<protocol::Answer>(r.value()).value;
  }

  bool exec(VehicleLink& link, const std::string& f, std::vector<protocol::Value> args = {}) {
    auto r = call(link, protocol::make_exec(0, f, std::move(args)));
    EXPECT_TRUE(r.ok()) << r.error().message;
    return r.ok() && std::get<protocol::Done>(r.value()).success;
  }

  asio::io_context io;
  vehicle::Simulation sim;
  std::unique_ptr<vehicle::VehicleServer> server;
  std::vector<std::string> vehicle_log;
};

// A client that speaks the protocol by hand, one line at a time, as a person
// at a terminal would (docs/protocol.md §9). It reads without blocking, so
// the vehicle can run on the same io_context between its reads.
struct LineClient {
  LineClient(asio::io_context& io, std::uint16_t port) : socket(io) {
    socket.connect({asio::ip::make_address("127.0.0.1"), port});
    socket.set_option(asio::ip::tcp::no_delay(true));
  }

  void say(const std::string& line) { asio::write(socket, asio::buffer(line + "\n")); }

  // Takes in whatever has arrived; sets closed at the end of the stream.
  void poll() {
    if (closed) return;
    socket.non_blocking(true);
    std::array<char, 4096> buf{};
    for (;;) {
      asio::error_code ec;
      std::size_t n = socket.read_some(asio::buffer(buf), ec);
      if (ec == asio::error::would_block) break;
      if (ec) {
        closed = true;
        break;
      }
      partial.append(buf.data(), n);
      for (auto nl = partial.find('\n'); nl != std::string::npos; nl = partial.find('\n')) {
        lines.push_back(partial.substr(0, nl));
        partial.erase(0, nl + 1);
      }
    }
    socket.non_blocking(false);
  }

  // The lines received so far that start with prefix.
  std::vector<std::string> starting(const std::string& prefix) const {
    std::vector<std::string> out;
    for (const auto& l : lines) {
      if (l.rfind(prefix, 0) == 0) out.push_back(l);
    }
    return out;
  }
  bool has(const std::string& prefix) const { return !starting(prefix).empty(); }

  // Runs io until a line starting with prefix has arrived (bounded).
  bool wait_for(asio::io_context& io, const std::string& prefix, std::chrono::milliseconds bound = 5000ms) {
    return run_until(
        io,
        [&] {
          poll();
          return has(prefix);
        },
        bound);
  }

  asio::ip::tcp::socket socket;
  std::vector<std::string> lines;  // without their newline
  std::string partial;
  bool closed = false;
};

// A fake vehicle on a free loopback port, played by a script on a thread of
// its own: hear() reads the link's next line into heard, say() writes. Once
// the link has closed, hear() hears nothing more and say() writes nothing,
// so a failing test ends its peer instead of hanging; join() also ends a
// peer the link never reached.
class ScriptedPeer {
 public:
  explicit ScriptedPeer(std::function<void(ScriptedPeer&)> script)
      : acceptor_(io_, {asio::ip::make_address("127.0.0.1"), 0}), socket_(io_) {
    thread_ = std::thread([this, script = std::move(script)] {
      acceptor_.accept(socket_, error_);
      accepted_ = true;
      if (!error_) script(*this);
    });
  }
  ~ScriptedPeer() { join(); }
  ScriptedPeer(const ScriptedPeer&) = delete;
  ScriptedPeer& operator=(const ScriptedPeer&) = delete;

  std::uint16_t port() const { return acceptor_.local_endpoint().port(); }

  void hear() {
    if (error_ || asio::read_until(socket_, in_, '\n', error_) == 0) return;
    std::istream is(&in_);
    std::string line;
    std::getline(is, line);
    heard_.push_back(line);
  }
  void say(const std::string& lines) {
    if (!error_) asio::write(socket_, asio::buffer(lines), error_);
  }

  // Waits for the script's end (close the link first) and gives what it heard.
  const std::vector<std::string>& join() {
    if (thread_.joinable()) {
      if (!accepted_) {  // the link never came: knock, so accept() returns
        asio::io_context io;
        asio::ip::tcp::socket knock(io);
        asio::error_code ignored;
        knock.connect({asio::ip::make_address("127.0.0.1"), port()}, ignored);
        knock.close(ignored);
      }
      thread_.join();
    }
    return heard_;
  }

 private:
  asio::io_context io_;
  asio::ip::tcp::acceptor acceptor_;
  asio::ip::tcp::socket socket_;
  asio::streambuf in_;
  asio::error_code error_;
  std::atomic<bool> accepted_{false};
  std::vector<std::string> heard_;
  std::thread thread_;
};

}  // namespace strata::tactical::testing
