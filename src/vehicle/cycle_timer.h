#pragma once
// The wall-clock cycle of a vehicle server (the Phoenix protocol's wall mode
// and `strata vehicle --imc`): one simulation cycle every cycle_s / speed
// wall seconds, each expiry counted from the previous one, never from now,
// so the loop does not drift by the time each cycle takes (a late cycle is
// caught up at once).
#include <chrono>

#include <asio.hpp>

namespace strata::vehicle {

inline void arm_next_cycle(asio::steady_timer& timer, double cycle_s, double speed) {
  const auto period =
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(cycle_s / speed));
  if (timer.expiry() == asio::steady_timer::time_point{}) {
    timer.expires_after(period);
  } else {
    timer.expires_at(timer.expiry() + period);
  }
}

}  // namespace strata::vehicle
