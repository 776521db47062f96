#pragma once
// Simulated time as it goes on the wire.
#include <cmath>

namespace strata::vehicle {

// Rounded to the microsecond: cycle * 0.1 is not exact in binary, and
// "5.6000000000000005" helps nobody.
inline double wire_time(double t_s) { return std::round(t_s * 1e6) / 1e6; }

}  // namespace strata::vehicle
