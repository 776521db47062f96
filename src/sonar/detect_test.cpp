// Detection on the synthesised tank: walls at their distances (±0.2 m), a
// target where it is (±0.3 m), no target where there is none; echo points.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "core/units.h"
#include "sonar/detect.h"
#include "sonar/processor.h"
#include "sonar/test_support.h"

namespace strata::sonar {
namespace {

using core::kRadPerDeg;
using testing::PingSynth;
using testing::SynthConfig;
using testing::SynthTarget;

Detection detect_after(PingSynth& synth, int sweeps) {
  Processor processor;
  std::optional<FrameReport> last;
  for (const auto& ping : synth.sweeps(sweeps)) {
    if (auto f = processor.add_ping(ping)) last = std::move(f);
  }
  if (auto f = processor.flush()) last = std::move(f);
  EXPECT_TRUE(last.has_value());
  return last ? last->detection : Detection{};
}

// The tank's walls a sweep sees plainly (first hit by 15 beams or more at
// an incidence under 60 degrees, for a strong echo), as name -> distance
// from the vehicle.
std::map<std::string, double> visible_walls(const SynthConfig& c) {
  PingSynth probe(c);
  std::map<std::string, int> hits;
  for (double bearing = -c.sweep_half_deg; bearing <= c.sweep_half_deg; bearing += c.step_deg) {
    const double compass = c.heading_deg + bearing;
    const double r = probe.wall_range(compass);
    if (r > c.range_m - 0.2) continue;
    const double dx = std::sin(compass * kRadPerDeg), dy = std::cos(compass * kRadPerDeg);
    const double x = c.x_m + r * dx, y = c.y_m + r * dy;
    const bool on_x_wall = std::abs(x) < 1e-6 || std::abs(x - c.tank_x_m) < 1e-6;
    if (std::abs(on_x_wall ? dx : dy) < 0.5) continue;
    ++hits[std::abs(x) < 1e-6                ? "west"
           : std::abs(x - c.tank_x_m) < 1e-6 ? "east"
           : std::abs(y) < 1e-6              ? "south"
                                             : "north"];
  }
  const std::map<std::string, double> distance{
      {"west", c.x_m}, {"east", c.tank_x_m - c.x_m}, {"south", c.y_m}, {"north", c.tank_y_m - c.y_m}};
  std::map<std::string, double> out;
  for (const auto& [wall, n] : hits) {
    if (n >= 15) out[wall] = distance.at(wall);
  }
  return out;
}

// Which tank wall a detected segment lies on, if any (within 0.2 m).
std::string wall_name(const Wall& w, const SynthConfig& c) {
  auto on = [](double a, double b, double v) { return std::abs(a - v) <= 0.2 && std::abs(b - v) <= 0.2; };
  if (on(w.x1_m, w.x2_m, 0.0)) return "west";
  if (on(w.x1_m, w.x2_m, c.tank_x_m)) return "east";
  if (on(w.y1_m, w.y2_m, 0.0)) return "south";
  if (on(w.y1_m, w.y2_m, c.tank_y_m)) return "north";
  return "none";
}

struct Place {
  double x_m, y_m, heading_deg;
};

// In the 12 x 8 m tank: two walls ahead, two abeam, three, corners near and far.
const Place kPlaces[] = {{7.0, 4.5, 45.0}, {3.0, 2.5, 200.0}, {6.0, 4.0, 90.0}, {2.5, 6.0, 300.0}, {9.5, 2.0, 160.0}};

TEST(Detect, WallsOfTheTankAreFoundAtTheirDistances) {
  for (const Place& place : kPlaces) {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      SCOPED_TRACE(::testing::Message() << "vehicle at (" << place.x_m << ", " << place.y_m << ") heading "
                                        << place.heading_deg << ", seed " << seed);
      SynthConfig c;
      c.x_m = place.x_m;
      c.y_m = place.y_m;
      c.heading_deg = place.heading_deg;
      c.seed = seed;
      PingSynth synth(c);
      const Detection d = detect_after(synth, 3);
      const auto expected = visible_walls(c);
      ASSERT_FALSE(expected.empty());
      std::map<std::string, double> found;
      for (const Wall& w : d.walls) {
        const std::string name = wall_name(w, c);
        EXPECT_NE("none", name) << "a wall where there is none: (" << w.x1_m << ", " << w.y1_m << ") - (" << w.x2_m
                                << ", " << w.y2_m << ")";
        EXPECT_EQ(0u, found.count(name)) << "the " << name << " wall twice";
        found[name] = w.distance_m;
      }
      for (const auto& [name, distance] : expected) {
        ASSERT_EQ(1u, found.count(name)) << "the " << name << " wall, " << distance << " m away, was not found";
        EXPECT_NEAR(distance, found[name], 0.2) << "the " << name << " wall";
      }
      EXPECT_FALSE(d.target) << "a target at (" << d.target->x_m << ", " << d.target->y_m << ") in an empty tank";
    }
  }
}

TEST(Detect, WallDistancesAreFromWhereTheVehicleIsWhileItMoves) {
  SynthConfig c;
  c.x_m = 3.0;
  c.y_m = 4.0;
  c.heading_deg = 90.0;
  c.vx_mps = 0.3;
  PingSynth synth(c);
  const Detection d = detect_after(synth, 4);
  const double x_now = synth.x_m() - c.vx_mps * c.ping_interval_s;  // at the last ping
  bool east = false;
  for (const Wall& w : d.walls) {
    if (wall_name(w, c) == "east") {
      east = true;
      EXPECT_NEAR(c.tank_x_m - x_now, w.distance_m, 0.2);
    }
  }
  EXPECT_TRUE(east);
}

struct TargetCase {
  Place vehicle;
  SynthTarget target;
};

TEST(Detect, TargetAtAKnownPlaceIsFound) {
  const TargetCase cases[] = {
      {{7.0, 4.5, 45.0}, {8.5, 6.0, 0.15}},
      {{4.0, 2.5, 350.0}, {3.2, 5.5, 0.2}},
      {{6.0, 4.0, 90.0}, {10.0, 2.8, 0.15}},
  };
  for (const auto& tc : cases) {
    for (std::uint64_t seed : {1u, 2u}) {
      SCOPED_TRACE(::testing::Message() << "target at (" << tc.target.x_m << ", " << tc.target.y_m << "), seed "
                                        << seed);
      SynthConfig c;
      c.x_m = tc.vehicle.x_m;
      c.y_m = tc.vehicle.y_m;
      c.heading_deg = tc.vehicle.heading_deg;
      c.target = tc.target;
      c.seed = seed;
      PingSynth synth(c);
      const Detection d = detect_after(synth, 3);
      ASSERT_TRUE(d.target) << "no target found";
      EXPECT_NEAR(tc.target.x_m, d.target->x_m, 0.3);
      EXPECT_NEAR(tc.target.y_m, d.target->y_m, 0.3);
      const double dx = tc.target.x_m - c.x_m, dy = tc.target.y_m - c.y_m;
      EXPECT_NEAR(std::hypot(dx, dy), d.target->range_m, 0.3);
      EXPECT_NEAR(normalise_deg(std::atan2(dx, dy) / kRadPerDeg - c.heading_deg), d.target->bearing_deg, 5.0);
      EXPECT_GE(d.target->pings, 3);
    }
  }
}

// Where a short piece of wall runs into a corner (too short to be a wall),
// its echoes are compact: they must not be taken for a target. (Without the
// two checks, lies along the beam and stands out, each of these was one.)
TEST(Detect, NoTargetWhereAShortPieceOfWallRunsIntoACorner) {
  struct Case {
    Place vehicle;
    std::uint64_t seed;
  };
  const Case cases[] = {{{7.02, 3.67, 358.4}, 266},
                        {{8.27, 2.44, 175.4}, 281},
                        {{10.19, 6.35, 111.7}, 274},
                        {{3.08, 4.26, 13.8}, 257},
                        {{10.70, 5.80, 55.2}, 291}};
  for (const auto& tc : cases) {
    SCOPED_TRACE(::testing::Message() << "vehicle at (" << tc.vehicle.x_m << ", " << tc.vehicle.y_m << ") heading "
                                      << tc.vehicle.heading_deg);
    SynthConfig c;
    c.x_m = tc.vehicle.x_m;
    c.y_m = tc.vehicle.y_m;
    c.heading_deg = tc.vehicle.heading_deg;
    c.seed = tc.seed;
    PingSynth synth(c);
    const Detection d = detect_after(synth, 3);
    EXPECT_FALSE(d.target) << "a target at (" << d.target->x_m << ", " << d.target->y_m << ")";
  }
}

TEST(Detect, EchoIsTheFirstStrongReturnPastTheMinimumRange) {
  protocol::SonarPing ping;
  ping.seq = 7;
  ping.heading_deg = 90.0f;  // beam along tank +x
  ping.x_m = 1.0f;
  ping.y_m = 2.0f;
  ping.range_m = 10.0f;
  ping.bins.assign(200, 20);
  ping.bins[0] = ping.bins[1] = ping.bins[2] = 200;  // ringing, inside min_range_m
  ping.bins[50] = 250;                               // one bin: speckle or a spike, not a return
  ping.bins[80] = 200;                               // the return: 4.0 - 4.1 m
  ping.bins[81] = 100;
  ping.bins[120] = ping.bins[121] = 250;  // a stronger return behind: not the first
  auto echo = find_echo(ping);
  ASSERT_TRUE(echo);
  const double range = (80.5 * 200 + 81.5 * 100) / 300 * 0.05;  // the intensity-weighted centre
  EXPECT_NEAR(range, echo->range_m, 1e-9);
  EXPECT_NEAR(1.0 + range, echo->x_m, 1e-6);
  EXPECT_NEAR(2.0, echo->y_m, 1e-6);
  EXPECT_EQ(7u, echo->seq);
}

TEST(Detect, NoEchoInOpenWaterOrFromAnEmptyPing) {
  protocol::SonarPing ping;
  ping.range_m = 10.0f;
  ping.bins.assign(200, 20);
  EXPECT_FALSE(find_echo(ping));
  // A loud ping (high median) needs a return well above its own noise.
  ping.bins.assign(200, 70);
  EXPECT_FALSE(find_echo(ping));
  ping.bins.clear();
  EXPECT_FALSE(find_echo(ping));
}

TEST(Detect, NormaliseDegrees) {
  EXPECT_DOUBLE_EQ(180.0, normalise_deg(-180.0));
  EXPECT_DOUBLE_EQ(-90.0, normalise_deg(270.0));
  EXPECT_DOUBLE_EQ(10.0, normalise_deg(730.0));
}

}  // namespace
}  // namespace strata::sonar
