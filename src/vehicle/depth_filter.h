#pragma once
// The Execution level's depth filter: an alpha-beta filter on the depth cell
// readings, run once a cycle, giving filtered depth (m, positive down) and
// depth rate (m/s, positive down). Its prediction can take an expected
// acceleration (the Simulation gives the heave model's, under the commanded
// thrust), which removes the plain filter's lag while the vehicle
// accelerates and keeps a coasting filter honest through a sensor dropout.
//
// It is off until start(); started, it initialises from the first reading it
// is given (depth = reading, rate = 0) and is ready() from then on. A cycle
// without a reading (sensor dropout) only predicts: depth += rate * dt +
// a dt^2 / 2, rate += a dt. With alpha 0.3 and beta 0.05 at 10 Hz the
// correction is close to critically damped (beta = alpha^2 / (2 - alpha)),
// and 2 cm of measurement noise gives about 1 cm on depth and 1.4 cm/s on
// rate.
#include <optional>

namespace strata::vehicle {

class DepthFilter {
 public:
  DepthFilter(double alpha, double beta, double dt_s) : alpha_(alpha), beta_(beta), dt_s_(dt_s) {}

  // Turns the filter on (idempotent; a running filter keeps its state).
  void start() { on_ = true; }
  bool on() const { return on_; }
  // On and initialised by a reading: depth_m() and rate_mps() are meaningful.
  bool ready() const { return ready_; }

  // One cycle. accel_mps2 is the acceleration the caller expects over the
  // cycle (its model of the vehicle under the thrust it commanded; 0 for a
  // plain alpha-beta filter): the prediction uses it, the reading corrects
  // it. Does nothing while the filter is off.
  void update(std::optional<double> reading_m, double accel_mps2 = 0.0);

  double depth_m() const { return depth_m_; }
  double rate_mps() const { return rate_mps_; }

 private:
  double alpha_;
  double beta_;
  double dt_s_;
  bool on_ = false;
  bool ready_ = false;
  double depth_m_ = 0.0;
  double rate_mps_ = 0.0;
};

}  // namespace strata::vehicle
