#pragma once
// The Tactical level's one interface to an Execution level (docs/imc.md):
// requests go out as protocol::Request values (exec/ask/ood with typed
// arguments, telemetry), and each is answered once, as a value: the
// vehicle's reply (an `err` included) or a typed error (core::ErrorCode
// Timeout, Closed, Protocol, InvalidInput, Io). Two implementations: VehicleLink (the Phoenix
// line protocol over TCP) and ImcLink (an IMC vehicle over UDP). The
// Tactical level, the safe end and the run know only this.
//
// Threads: every method must be called on the link's io_context thread, and
// every handler runs there.
#include <chrono>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "core/result.h"
#include "protocol/message.h"

namespace strata::tactical {

// The reply to one request: ok/done/answer/pong/welcome, or protocol::Err
// when the vehicle refused it (its code and message); or an error whose code
// says what happened (ErrorCode::Timeout; Closed: no link, or it went;
// Protocol: the vehicle's answer could not be used (malformed, or `err 0
// busy`); InvalidInput: the link cannot carry the request (an IMC vehicle has
// no such function); Io: could not connect). tactical/call_error.h maps them.
using ReplyHandler = std::function<void(core::Result<protocol::VehicleMessage>)>;

class ExecutionLink : public std::enable_shared_from_this<ExecutionLink> {
 public:
  // While a Hold is alive a lockstep link sends no advance (VehicleLink);
  // links on the vehicle's own clock ignore it. Move-only; letting it go
  // (release() or destruction) tells the link. A Hold may outlive its link.
  class Hold {
   public:
    Hold() = default;
    Hold(Hold&& other) noexcept : link_(std::move(other.link_)) { other.link_.reset(); }
    Hold& operator=(Hold&& other) noexcept;
    Hold(const Hold&) = delete;
    Hold& operator=(const Hold&) = delete;
    ~Hold() { release(); }
    void release();

   private:
    friend class ExecutionLink;
    explicit Hold(std::weak_ptr<ExecutionLink> link) : link_(std::move(link)) {}
    std::weak_ptr<ExecutionLink> link_;
  };

  ExecutionLink() = default;
  ExecutionLink(const ExecutionLink&) = delete;
  ExecutionLink& operator=(const ExecutionLink&) = delete;
  virtual ~ExecutionLink() = default;

  // Sends request (its id is assigned here and returned) and calls handler
  // exactly once, never before send() returns: with the reply, or with an
  // error. timeout: wall clock; sim_timeout_s: the vehicle's clock.
  virtual protocol::RequestId send(protocol::Request request, ReplyHandler handler,
                                   std::optional<std::chrono::milliseconds> timeout = std::nullopt,
                                   std::optional<double> sim_timeout_s = std::nullopt) = 0;
  virtual bool connected() const = 0;
  virtual std::chrono::milliseconds default_timeout() const = 0;
  // The vehicle's time as far as the link knows it; nullopt before it told.
  virtual std::optional<double> sim_time_s() const = 0;
  // Closes the link; pending requests fail with Closed.
  virtual void close() = 0;

  // Keeps a lockstep link from moving the vehicle's time until let go.
  Hold hold();

  void on_telemetry(std::function<void(const protocol::Telemetry&)> f) { on_telemetry_ = std::move(f); }
  void on_event(std::function<void(const protocol::Event&)> f) { on_event_ = std::move(f); }
  // Called once when the link is gone for good.
  void on_lost(std::function<void(const core::Error&)> f) { on_lost_ = std::move(f); }
  // The vehicle is there but no longer takes this run's commands (an IMC
  // plan replaced by another controller, or timed out): the run must end,
  // and may still try to surface the vehicle.
  void on_fault(std::function<void(const std::string&)> f) { on_fault_ = std::move(f); }
  // What the vehicle sent that could not be used (logged by the caller).
  void on_garbage(std::function<void(const std::string&)> f) { on_garbage_ = std::move(f); }

 protected:
  // A Hold was let go (holds() already counts it out).
  virtual void hold_released() {}
  std::size_t holds() const { return holds_; }

  std::function<void(const protocol::Telemetry&)> on_telemetry_;
  std::function<void(const protocol::Event&)> on_event_;
  std::function<void(const core::Error&)> on_lost_;
  std::function<void(const std::string&)> on_fault_;
  std::function<void(const std::string&)> on_garbage_;

 private:
  std::size_t holds_ = 0;
};

}  // namespace strata::tactical
