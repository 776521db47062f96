// The sub-step's shortcuts (drag_axis.h): the lags worked out once a cycle
// and an axis at rest skipped. Each must move the vehicle bit for bit as the
// plain formulas did (for the finite values parameters and scenarios are
// checked to be), so a run's log does not change by a single digit.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/units.h"
#include "vehicle/drag_axis.h"
#include "vehicle/params.h"
#include "vehicle/surge.h"
#include "vehicle/sway.h"
#include "vehicle/yaw.h"

namespace strata::vehicle {
namespace {

// The sub-step as it was written before the shortcuts.
void plain_drag_axis(const DragAxis& a, double cmd_n, double limit_n, double h_s, double& force_n, double& speed) {
  const double target = std::clamp(cmd_n, -limit_n, limit_n);
  const double lag = a.lag_s > 0.0 ? 1.0 - std::exp(-h_s / a.lag_s) : 1.0;
  force_n += (target - force_n) * lag;
  const double force = force_n - a.drag_coeff * speed * std::abs(speed);
  speed += h_s * force / a.mass_kg;
}

void plain_yaw(const VehicleParams& p, double moment_cmd_nm, double moment_limit_nm, double h_s, YawState& s) {
  const double target = std::clamp(moment_cmd_nm, -moment_limit_nm, moment_limit_nm);
  const double lag = p.transverse_lag_s > 0.0 ? 1.0 - std::exp(-h_s / p.transverse_lag_s) : 1.0;
  s.moment_nm += (target - s.moment_nm) * lag;
  const double kRad = core::kRadPerDeg;
  double r = s.rate_dps * kRad;
  r += h_s * (s.moment_nm - p.yaw_drag_coeff * r * std::abs(r)) / p.total_yaw_inertia_kgm2();
  s.rate_dps = r / kRad;
  s.heading_deg = wrap_heading_deg(s.heading_deg + h_s * s.rate_dps);
}

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

// Values an axis meets: both zeros, tiny and large, and random ones.
std::vector<double> awkward_values(std::mt19937_64& rng, int random_count) {
  std::vector<double> v = {0.0, -0.0, 1e-300, -1e-300, std::numeric_limits<double>::denorm_min(), 0.5, -3.0, 40.0};
  std::uniform_real_distribution<double> d(-20.0, 20.0);
  for (int i = 0; i < random_count; ++i) v.push_back(d(rng));
  return v;
}

TEST(Substep, AnAxisMovesBitForBitAsThePlainFormulasWithTheLagWorkedOutOnceAndRestSkipped) {
  std::mt19937_64 rng(41);
  const VehicleParams p = default_params();
  const double h = p.cycle_s / p.substeps;
  const auto values = awkward_values(rng, 12);
  int at_rest = 0;
  for (const DragAxis axis : {DragAxis{p.motor_lag_s, p.surge_drag_coeff, p.total_surge_mass_kg()},
                              DragAxis{p.transverse_lag_s, p.sway_drag_coeff, p.total_sway_mass_kg()},
                              DragAxis{0.0, p.sway_drag_coeff, p.total_sway_mass_kg()}}) {
    const double lag = lag_fraction(h, axis.lag_s);
    for (const double cmd : values) {
      for (const double force : values) {
        for (const double speed : values) {
          for (const double limit : {18.0, 0.0}) {  // 0: thrusters that give nothing
            double f1 = force, s1 = speed, f2 = force, s2 = speed;
            plain_drag_axis(axis, cmd, limit, h, f1, s1);
            advance_drag_axis(axis, cmd, limit, h, lag, f2, s2);
            ASSERT_EQ(bits(f1), bits(f2)) << cmd << " " << force << " " << speed << " " << limit;
            ASSERT_EQ(bits(s1), bits(s2)) << cmd << " " << force << " " << speed << " " << limit;
            at_rest += (cmd == 0.0 || limit == 0.0) && bits(force) == 0 && bits(speed) == 0;
          }
        }
      }
    }
  }
  EXPECT_GT(at_rest, 0);  // the skipped case was among them
}

TEST(Substep, SurgeSwayAndYawWithTheLagGivenMoveAsThePlainFormulas) {
  std::mt19937_64 rng(7);
  const VehicleParams p = default_params();
  const double h = p.cycle_s / p.substeps;
  const auto values = awkward_values(rng, 6);
  for (const double cmd : values) {
    for (const double a : values) {
      for (const double b : values) {
        SurgeState u1{a, b}, u2{a, b};
        plain_drag_axis({p.motor_lag_s, p.surge_drag_coeff, p.total_surge_mass_kg()}, cmd, p.max_surge_thrust_n(), h,
                        u1.thrust_n, u1.speed_mps);
        advance_surge(p, cmd, p.max_surge_thrust_n(), h, lag_fraction(h, p.motor_lag_s), u2);
        EXPECT_TRUE(bits(u1.speed_mps) == bits(u2.speed_mps) && bits(u1.thrust_n) == bits(u2.thrust_n));
        SwayState w1{a, b}, w2{a, b};
        plain_drag_axis({p.transverse_lag_s, p.sway_drag_coeff, p.total_sway_mass_kg()}, cmd, p.max_sway_force_n(), h,
                        w1.force_n, w1.speed_mps);
        advance_sway(p, cmd, p.max_sway_force_n(), h, lag_fraction(h, p.transverse_lag_s), w2);
        EXPECT_TRUE(bits(w1.speed_mps) == bits(w2.speed_mps) && bits(w1.force_n) == bits(w2.force_n));
        YawState y0{std::abs(a) * 9.0, b, cmd}, y1 = y0, y2 = y0;
        plain_yaw(p, cmd, p.max_yaw_moment_nm(), h, y1);
        advance_yaw(p, cmd, p.max_yaw_moment_nm(), h, lag_fraction(h, p.transverse_lag_s), y2);
        EXPECT_TRUE(bits(y1.heading_deg) == bits(y2.heading_deg) && bits(y1.rate_dps) == bits(y2.rate_dps) &&
                    bits(y1.moment_nm) == bits(y2.moment_nm));
      }
    }
  }
}

TEST(Substep, TheLagFractionIsTheExactStepOfTheLagAndAllOfItWithoutOne) {
  EXPECT_EQ(bits(1.0 - std::exp(-0.01 / 0.3)), bits(lag_fraction(0.01, 0.3)));
  EXPECT_EQ(1.0, lag_fraction(0.01, 0.0));
  EXPECT_EQ(1.0, lag_fraction(0.01, -1.0));
  EXPECT_TRUE(plus_zero(0.0));
  EXPECT_FALSE(plus_zero(-0.0));
  EXPECT_FALSE(plus_zero(1e-300));
}

}  // namespace
}  // namespace strata::vehicle
