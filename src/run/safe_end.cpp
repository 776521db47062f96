#include "run/safe_end.h"

#include <fmt/format.h>

namespace strata::run {
namespace {

constexpr const char* kShutdownNetwork = "shutdown_network";
constexpr const char* kSurface = "surface";
constexpr const char* kSurfaceReached = "surface_reached";
constexpr const char* kSleep = "sleep";
constexpr int kSurfaceLimitS = 120;

using CallResult = tactical::CallResult;

}  // namespace

SafeEnd::SafeEnd(strategic::Tactics& vehicle, const tactical::Catalogue& catalogue, Say say)
    : vehicle_(vehicle), catalogue_(catalogue), say_(std::move(say)) {}

bool SafeEnd::possible() const { return catalogue_.find(kShutdownNetwork) != nullptr; }

bool SafeEnd::can_surface(bool link_gone) const {
  return !link_gone && catalogue_.find(kSurface) && catalogue_.find(kSurfaceReached) && catalogue_.find(kSleep);
}

std::string SafeEnd::plan(bool link_gone) const {
  return can_surface(link_gone)
             ? fmt::format("ask {}; if 0, exec {} and ask until 1; ood {}", kSurfaceReached, kSurface, kShutdownNetwork)
             : fmt::format("ood {}", kShutdownNetwork);
}

void SafeEnd::run(bool link_gone, std::function<void()> done) {
  done_ = std::move(done);
  if (!can_surface(link_gone)) {
    send_done();
    return;
  }
  // Already at the surface (or the vehicle will not say): done at once.
  vehicle_.call(kSurfaceReached, {}, [this](CallResult at_surface) {
    if (!done_) return;  // abandoned
    if (!at_surface || at_surface.value().value) {
      if (!at_surface) say_(fmt::format("ask {} failed: {}", kSurfaceReached, at_surface.error().message));
      surfaced_ = at_surface.ok();
      send_done();
      return;
    }
    surface_commanded_ = true;
    vehicle_.call(kSurface, {}, [this](CallResult r) {
      if (!done_) return;
      if (!r || !r.value().value) {
        say_(r ? fmt::format("exec {}: the vehicle answered 0", kSurface)
               : fmt::format("exec {} failed: {}", kSurface, r.error().message));
        send_done();
        return;
      }
      poll(kSurfaceLimitS);
    });
  });
}

void SafeEnd::poll(int seconds_left) {
  vehicle_.call(kSurfaceReached, {}, [this, seconds_left](CallResult r) {
    if (!done_) return;
    if (r && r.value().value) {
      surfaced_ = true;
      send_done();
    } else if (!r || seconds_left <= 0) {
      say_(r ? fmt::format("the vehicle did not reach the surface in {} s", kSurfaceLimitS)
             : fmt::format("ask {} failed: {}", kSurfaceReached, r.error().message));
      send_done();
    } else {
      vehicle_.call(kSleep, {tactical::Value::of(1.0)}, [this, seconds_left](const CallResult& s) {
        if (!done_) return;
        if (!s) {
          send_done();
          return;
        }
        poll(seconds_left - 1);
      });
    }
  });
}

void SafeEnd::send_done() {
  shutdown_sent_ = true;
  vehicle_.call(kShutdownNetwork, {}, [this](const CallResult& r) {
    if (!done_) return;
    if (!r) {
      shutdown_error_ = r.error().message;
      say_(fmt::format("ood {} failed: {}", kShutdownNetwork, r.error().message));
    }
    finish();
  });
}

void SafeEnd::abandon() {
  if (done_) say_("the safe end was cut short: the vehicle's last answers are not waited for");
  finish();
}

void SafeEnd::finish() {
  if (!done_) return;
  auto done = std::move(done_);
  done_ = nullptr;
  done();
}

}  // namespace strata::run
