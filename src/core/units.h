#pragma once
// Unit conversions shared by the vehicle model and the Sonar Manager.
#include <numbers>

namespace strata::core {

inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;  // radians in one degree

}  // namespace strata::core
