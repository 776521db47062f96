#pragma once
// The two clocks of a run (design.md §2.4), never mixed within one run:
//  - VirtualClock: simulated time, advanced only by the simulation (lockstep);
//  - WallClock: a monotonic wall clock scaled by a speed factor.
// Components that need time take a Clock&; nothing else reads the system clock.
#include <chrono>
#include <string>

namespace strata::core {

class Clock {
 public:
  virtual ~Clock() = default;
  // Seconds since the clock's epoch (the start of the run).
  virtual double now_s() const = 0;
};

class VirtualClock final : public Clock {
 public:
  double now_s() const override { return now_s_; }
  // Precondition: t_s >= now_s() (time never runs backwards).
  void set(double t_s) { now_s_ = t_s; }

 private:
  double now_s_ = 0.0;
};

class WallClock final : public Clock {
 public:
  // speed: simulated seconds per wall second (1 = real time).
  explicit WallClock(double speed = 1.0)
      : speed_(speed), start_(std::chrono::steady_clock::now()) {}
  double now_s() const override {
    std::chrono::duration<double> d = std::chrono::steady_clock::now() - start_;
    return d.count() * speed_;
  }
  double speed() const { return speed_; }

 private:
  double speed_;
  std::chrono::steady_clock::time_point start_;
};

// The calendar time as ISO-8601 UTC ("2026-11-21T06:25:00.123Z"), for wall_*
// fields of logs only.
std::string wall_time_iso8601();

}  // namespace strata::core
