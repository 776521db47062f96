#include "vehicle/depth_filter.h"

namespace strata::vehicle {

void DepthFilter::update(std::optional<double> reading_m, double accel_mps2) {
  if (!on_) return;
  if (!ready_) {
    if (!reading_m) return;
    depth_m_ = *reading_m;
    rate_mps_ = 0.0;
    ready_ = true;
    return;
  }
  const double predicted = depth_m_ + rate_mps_ * dt_s_ + 0.5 * accel_mps2 * dt_s_ * dt_s_;
  rate_mps_ += accel_mps2 * dt_s_;
  if (!reading_m) {
    depth_m_ = predicted;
    return;
  }
  const double residual = *reading_m - predicted;
  depth_m_ = predicted + alpha_ * residual;
  rate_mps_ += beta_ / dt_s_ * residual;
}

}  // namespace strata::vehicle
