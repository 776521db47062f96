#pragma once
// What the open-water tests share (open_water_test.cpp, sway_test.cpp): an
// open-water scenario from a few lines of TOML, and a simulation of it with
// its network started.
#include <string>

#include <gtest/gtest.h>

#include "vehicle/simulation.h"

namespace strata::vehicle::test_support {

inline Scenario open_water(const std::string& extra = "") {
  auto s = parse_scenario("seed = 7\n[world]\nkind = \"open_water\"\n" + extra, "ow.toml");
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
  return s.ok() ? s.value() : Scenario{};
}

inline Simulation started(const Scenario& s) {
  Simulation sim(default_params(), s);
  EXPECT_TRUE(sim.start_network().ok());
  return sim;
}

}  // namespace strata::vehicle::test_support
