#include "run/bound_options.h"

#include <algorithm>
#include <cmath>

namespace strata::run {

// From `exec surface` at depth_m to the vehicle at the surface (its
// surface_reached), at most: an estimate from the vehicle's parameters. Full
// upward thrust and the buoyancy against the drag give the top ascent rate;
// the sliding-mode law slows the last metres (it holds w = -lambda z); the
// thrusters take a few time constants to reach full thrust. A 20 % margin
// covers what the estimate leaves out (the filter's lag, a surge speed
// still on). docs/verification.md, "Reaction time".
double ascent_estimate_s(const vehicle::VehicleParams& p, double depth_m) {
  const double up_n = 2.0 * p.thruster_max_n + std::max(0.0, p.buoyancy_n);
  const double w_max = std::sqrt(up_n / p.drag_coeff);
  const double slow_from_m = w_max / p.ctrl_lambda_per_s;  // below this the law slows the ascent
  double t = 3.0 * p.thruster_lag_s;
  if (depth_m > slow_from_m) {
    t += (depth_m - slow_from_m) / w_max;
    depth_m = slow_from_m;
  }
  if (depth_m > p.surface_depth_m) t += std::log(depth_m / p.surface_depth_m) / p.ctrl_lambda_per_s;
  return 1.2 * t;
}

coral::BoundOptions bound_options(const tactical::Catalogue& cat, double depth_max_m, std::uint64_t max_states) {
  coral::BoundOptions bo;
  bo.max_states = max_states;
  bo.ascent_s = ascent_estimate_s(vehicle::default_params(), depth_max_m);
  bo.primitive = [&cat](std::string_view name) -> std::optional<coral::PrimitiveTiming> {
    const tactical::Primitive* p = cat.find(name);
    if (!p) return std::nullopt;
    coral::PrimitiveTiming t;
    t.reply_s = cat.reply_bound_s(*p);
    if (!p->timeout_plus_arg.empty()) {
      for (std::size_t i = 0; i < p->args.size(); ++i) {
        if (p->args[i].name != p->timeout_plus_arg) continue;
        t.wait_arg = i;
        t.wait_arg_max = p->args[i].max.value_or(0.0);
      }
    }
    return t;
  };
  return bo;
}

}  // namespace strata::run
