#pragma once
// The wall-clock cycle of a vehicle server (the Phoenix protocol's wall mode
// and `strata vehicle --imc`): one simulation cycle every cycle_s / speed
// wall seconds, each expiry counted from the previous one, never from now,
// so the loop does not drift by the time each cycle takes. A loop that fell
// behind catches up at once (the Phoenix's wall mode), or, with
// max_behind_cycles, by at most that many cycles: past it the simulation
// takes up from now, slower than real time for a moment, rather than run a
// burst of cycles ahead of the requests waiting in its socket (an IMC
// vehicle whose clock is its controller's: a burst of 10 simulated seconds
// would time out a request it had not yet read).
#include <chrono>
#include <optional>

#include <asio.hpp>

namespace strata::vehicle {

inline void arm_next_cycle(asio::steady_timer& timer, double cycle_s, double speed,
                           std::optional<int> max_behind_cycles = std::nullopt) {
  const auto period =
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(cycle_s / speed));
  const auto now = std::chrono::steady_clock::now();
  if (timer.expiry() == asio::steady_timer::time_point{} ||
      (max_behind_cycles && timer.expiry() + period * *max_behind_cycles < now)) {
    timer.expires_at(now + period);
  } else {
    timer.expires_at(timer.expiry() + period);
  }
}

}  // namespace strata::vehicle
