#pragma once
// The vehicle's part of a run's one safe end (docs/architecture.md, "One
// run, one safe end"): after a mission that did not complete and did not
// run its own abort path to `done`, while the link still works, surface the
// vehicle if it is under water, then send Figure 10's `done` (`ood
// shutdown_network`):
//
//   ask surface_reached; if 0: exec surface, then ask surface_reached once
//   per simulated second (exec sleep 1 between) for at most 120 s;
//   then ood shutdown_network, whatever happened before.
//
// On a lost link only the shutdown is tried: surfacing is then the vehicle's
// own watchdog's job. abandon() (a second Ctrl-C) ends the procedure at once.
//
// It calls the vehicle through the Strategic level's interface
// (strategic::Tactics): a run gives it the Tactical level itself (never the
// scripted answers of --answers), a test a fake vehicle it answers by hand.
//
// Threads: one; the event loop's. The object must outlive the procedure.
#include <functional>
#include <string>

#include "strategic/tactics.h"
#include "tactical/catalogue.h"

namespace strata::run {

class SafeEnd {
 public:
  using Say = std::function<void(const std::string&)>;
  // vehicle and catalogue must outlive this object.
  SafeEnd(strategic::Tactics& vehicle, const tactical::Catalogue& catalogue, Say say);

  // The catalogue has the shutdown primitive: there is something to do.
  bool possible() const;
  // What run() will send, for the console and the log.
  std::string plan(bool link_gone) const;
  // Runs the procedure; done is called once, from the event loop, at its end
  // (or at abandon()).
  void run(bool link_gone, std::function<void()> done);
  // Stops waiting for the vehicle: done is called now (replies that come
  // later are ignored). Does nothing when the procedure is not running.
  void abandon();

  bool shutdown_sent() const { return shutdown_sent_; }
  const std::string& shutdown_error() const { return shutdown_error_; }  // "" if answered
  bool surface_commanded() const { return surface_commanded_; }
  bool surfaced() const { return surfaced_; }  // surface_reached answered 1

 private:
  bool can_surface(bool link_gone) const;
  void poll(int seconds_left);
  void send_done();
  void finish();

  strategic::Tactics& vehicle_;
  const tactical::Catalogue& catalogue_;
  Say say_;
  std::function<void()> done_;
  bool shutdown_sent_ = false;
  bool surface_commanded_ = false;
  bool surfaced_ = false;
  std::string shutdown_error_;
};

}  // namespace strata::run
