// Campaign specs: what they make, and every way they can be wrong, located.
#include "campaign/spec.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "campaign/campaign_test_support.h"
#include "campaign/cases.h"
#include "core/test_fifo.h"

namespace strata::campaign {
namespace {

using testing::error_of;
using testing::parse;
using testing::spec_text;
using testing::TempDir;

// spec_text, parse and error_of: campaign_test_support.h.

TEST(CampaignSpec, AGridCountsItsEndsAndTheSpecMultipliesOut) {
  auto spec = parse(spec_text(R"(seeds = [1, 2, 3]
[[family]]
fault = "none"
[[family]]
fault = "leak"
at_s = { from = 0, to = 2, step = 0.5 }
[[family]]
fault = "weak_thrusters"
at_s = [1, 5]
health = { from = 0.4, to = 1.0, step = 0.2 }
)"));
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  const Spec& s = spec.value();
  EXPECT_EQ((std::vector<double>{0, 0.5, 1, 1.5, 2}), s.families[1].at_s);
  EXPECT_EQ((std::vector<double>{0.4, 0.6, 0.8, 1.0}), s.families[2].health);
  EXPECT_EQ(3u * (1 + 5 + 2 * 4), s.case_count());
  EXPECT_EQ("default", s.families[0].expect);
}

TEST(CampaignSpec, CasesComeInTheDocumentedOrderAndEveryCombinationOnce) {
  auto spec = parse(spec_text(R"(seeds = { from = 7, count = 2 }
[[family]]
fault = "weak_thrusters"
at_s = [1, 5]
health = [0.5, 0.9]
)"));
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  std::vector<std::string> got;
  for (std::uint64_t i = 0; i < spec.value().case_count(); ++i) {
    const Case c = case_at(spec.value(), i);
    got.push_back(fault_text(c) + " seed " + std::to_string(c.seed));
  }
  EXPECT_EQ(
      (std::vector<std::string>{"weak_thrusters health 0.5 at 1 s seed 7", "weak_thrusters health 0.5 at 1 s seed 8",
                                "weak_thrusters health 0.9 at 1 s seed 7", "weak_thrusters health 0.9 at 1 s seed 8",
                                "weak_thrusters health 0.5 at 5 s seed 7", "weak_thrusters health 0.5 at 5 s seed 8",
                                "weak_thrusters health 0.9 at 5 s seed 7", "weak_thrusters health 0.9 at 5 s seed 8"}),
      got);
}

TEST(CampaignSpec, SampledAxesAreTheSameEveryTimeAndMoveWithTheSampleSeed) {
  const std::string body = R"(
[[family]]
fault = "leak"
at_s = { from = 0, to = 30, sampled = 50 }
)";
  auto a = parse(spec_text("sample_seed = 5\n" + body));
  auto b = parse(spec_text("sample_seed = 5\n" + body));
  auto c = parse(spec_text("sample_seed = 6\n" + body));
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  EXPECT_EQ(a.value().families[0].at_s, b.value().families[0].at_s);
  EXPECT_NE(a.value().families[0].at_s, c.value().families[0].at_s);
  const auto& at = a.value().families[0].at_s;
  ASSERT_EQ(50u, at.size());
  EXPECT_TRUE(std::is_sorted(at.begin(), at.end()));
  EXPECT_GE(at.front(), 0.0);
  EXPECT_LE(at.back(), 30.0);
  EXPECT_GT(at.back() - at.front(), 15.0) << "50 uniform draws over 30 s should spread";
}

TEST(CampaignSpec, TheScenarioOfACaseReadsBackAsTheSameFault) {
  auto spec = parse(spec_text(R"(
[[family]]
fault = "link_loss"
at_s = 2.5
forever = true
[[family]]
fault = "sensor_dropout"
at_s = 3
duration_s = 0.5
)"));
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  for (std::uint64_t i = 0; i < spec.value().case_count(); ++i) {
    const Case c = case_at(spec.value(), i);
    auto scenario = vehicle::parse_scenario(scenario_toml(spec.value(), c), "case.toml");
    ASSERT_TRUE(scenario.ok()) << scenario.error().message;
    ASSERT_EQ(1u, scenario.value().faults.size());
    EXPECT_EQ(*c.fault, scenario.value().faults[0]);
    EXPECT_EQ(c.seed, scenario.value().seed);
  }
}

TEST(CampaignSpec, PerturbedParametersAreAxesInsideTheFaultsAndOutsideTheSeeds) {
  auto spec = parse(spec_text(R"(seeds = [1, 2]
[[family]]
fault = "leak"
at_s = [3, 9]
perturb = { thrusters.max_n = [15, 18], hull.mass_kg = [170, 180] }
)"));
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  const Spec& s = spec.value();
  ASSERT_EQ(2u, s.families[0].perturb.size());
  EXPECT_EQ("hull.mass_kg", s.families[0].perturb[0].param) << "config/phoenix.toml's order, not the spec's";
  EXPECT_EQ(2u * 2 * 2 * 2, s.case_count());
  std::vector<std::string> got;
  for (std::uint64_t i = 0; i < s.case_count(); ++i) {
    const Case c = case_at(s, i);
    got.push_back(fault_text(c) + " " + params_text(c) + " seed " + std::to_string(c.seed));
  }
  EXPECT_EQ("leak at 3 s hull.mass_kg=170 thrusters.max_n=15 seed 1", got[0]);
  EXPECT_EQ("leak at 3 s hull.mass_kg=170 thrusters.max_n=15 seed 2", got[1]);
  EXPECT_EQ("leak at 3 s hull.mass_kg=170 thrusters.max_n=18 seed 1", got[2]);
  EXPECT_EQ("leak at 3 s hull.mass_kg=180 thrusters.max_n=15 seed 1", got[4]);
  EXPECT_EQ("leak at 9 s hull.mass_kg=180 thrusters.max_n=18 seed 2", got[15]);
  const Case c = case_at(s, 6);
  EXPECT_EQ(180.0, case_params(s, c).mass_kg);
  EXPECT_EQ(18.0, case_params(s, c).thruster_max_n);
  const auto inputs = case_inputs(s, c);
  EXPECT_EQ(180.0, inputs["params"]["hull.mass_kg"]);
  EXPECT_EQ(18.0, inputs["params"]["thrusters.max_n"]);
  EXPECT_NE(std::string::npos, scenario_toml(s, c).find("hull.mass_kg=180 thrusters.max_n=18"));
}

TEST(CampaignSpec, ANominalFamilyPerturbsAloneAndTheSpecsPerturbationsReachEveryFamily) {
  auto spec = parse(spec_text(R"(perturb = { hull.buoyancy_n = [2, 5, 8] }
[[family]]
fault = "none"
[[family]]
name = "heavy"
fault = "none"
perturb = { "hull.buoyancy_n" = -1, hull.mass_kg = 200 }
)"));
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  const Spec& s = spec.value();
  EXPECT_EQ(3u + 1u, s.case_count());
  EXPECT_EQ("hull.buoyancy_n=8", params_text(case_at(s, 2)));
  EXPECT_EQ("hull.mass_kg=200 hull.buoyancy_n=-1", params_text(case_at(s, 3))) << "the family's value wins";
  EXPECT_TRUE(s.perturbs());
  auto plain = parse(spec_text("[[family]]\nfault = \"none\"\n"));
  ASSERT_TRUE(plain.ok());
  EXPECT_FALSE(plain.value().perturbs());
  EXPECT_FALSE(case_inputs(plain.value(), case_at(plain.value(), 0)).contains("params"));
}

TEST(CampaignSpec, SampledParametersAreTheSameEveryTimeWithinTheirRange) {
  const std::string body = R"(
[[family]]
fault = "none"
perturb = { hull.mass_kg = { from = 40, to = 48, sampled = 4 } }
)";
  auto a = parse(spec_text("sample_seed = 3\n" + body));
  auto b = parse(spec_text("sample_seed = 3\n" + body));
  auto c = parse(spec_text("sample_seed = 4\n" + body));
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  const auto& values = a.value().families[0].perturb[0].values;
  EXPECT_EQ(values, b.value().families[0].perturb[0].values);
  EXPECT_NE(values, c.value().families[0].perturb[0].values);
  ASSERT_EQ(4u, values.size());
  for (double v : values) {
    EXPECT_GE(v, 40.0);
    EXPECT_LE(v, 48.0);
  }
}

TEST(CampaignSpec, UnknownOrImpossibleParametersAreLocatedAndNameTheValidOnes) {
  const auto family = [](const std::string& perturb) {
    return spec_text("[[family]]\nfault = \"none\"\nperturb = " + perturb + "\n");
  };
  const std::string unknown = error_of(family("{ mass_kg = [40, 48] }"));
  EXPECT_NE(std::string::npos, unknown.find("c.toml:4:13: unknown vehicle parameter 'mass_kg'; did you mean "
                                            "hull.mass_kg?"))
      << unknown;
  EXPECT_NE(std::string::npos, unknown.find("hull: mass_kg, added_mass_kg, drag_coeff, buoyancy_n; thrusters: "
                                            "max_n, lag_s;"))
      << unknown;
  EXPECT_NE(std::string::npos, error_of(family("{ thrusters.thrust_n = 30 }"))
                                   .find("c.toml:4:23: unknown vehicle parameter 'thrusters.thrust_n'"));
  EXPECT_NE(std::string::npos,
            error_of(family("{ hull = { from = 1, to = 2, step = 1 } }")).find("unknown vehicle parameter 'hull'"));
  EXPECT_NE(std::string::npos,
            error_of(family("{ hull.mass_kg = 0 }")).find("c.toml:4:28: 'hull.mass_kg' must be > 0 (it is 0)"));
  EXPECT_NE(std::string::npos, error_of(family("{ hull.mass_kg = [175, -1] }")).find("'hull.mass_kg' must be > 0"));
  EXPECT_NE(std::string::npos, error_of(family("{ hull.mass_kg = nan }")).find("(it is nan)"));
  EXPECT_NE(
      std::string::npos,
      error_of(family("{ hull.buoyancy_n = inf }")).find("'hull.buoyancy_n' must be a finite number (it is inf)"));
  EXPECT_NE(std::string::npos, error_of(family("{ filter.alpha = { from = 0.5, to = 2, step = 0.5 } }"))
                                   .find("'filter.alpha.to' must be in [0, 1] (it is 2)"));
  EXPECT_NE(std::string::npos,
            error_of(family("{ simulation.substeps = 2.5 }")).find("'simulation.substeps' = 2.5 is not a whole"));
  EXPECT_NE(std::string::npos, error_of(family("{ simulation.substeps = { from = 1, to = 9, sampled = 3 } }"))
                                   .find("is a whole number: give a list or a grid"));
  EXPECT_NE(std::string::npos, error_of(family("[1, 2]")).find("'perturb' must be a table of vehicle parameters"));
  EXPECT_NE(std::string::npos, error_of(family("{}")).find("'perturb' must be a table"));
  // Each value is possible, but not together: surface_depth_m 7 is below a 6 m tank's bottom.
  const std::string together = error_of(family("{ detection.surface_depth_m = [0.15, 7] }"));
  EXPECT_NE(std::string::npos, together.find("c.toml:4:11: family 'none' makes a vehicle that cannot be "
                                             "(detection.surface_depth_m=7): detection.surface_depth_m must be less "
                                             "than simulation.tank_depth_m"))
      << together;
  EXPECT_NE(std::string::npos, error_of(family("{ \"hull.mass_kg\" = 170, hull.mass_kg = 180 }"))
                                   .find("'hull.mass_kg' is perturbed twice in one 'perturb'"));
  // The cruise speed within the top speed: a weaker motor with the same cruise speed cannot be.
  EXPECT_NE(std::string::npos, error_of(family("{ surge.motor_max_n = [12, 1], hull.mass_kg = [170, 180] }"))
                                   .find("(surge.motor_max_n=1): guidance.cruise_speed_mps must not exceed"));
  EXPECT_NE(std::string::npos, error_of(spec_text("perturb = { hull.mas_kg = 1 }\n[[family]]\nfault = \"none\"\n"))
                                   .find("c.toml:2:18: unknown vehicle parameter 'hull.mas_kg'"));
}

TEST(CampaignSpec, AHugePerturbationIsRefusedBeforeAnythingIsMade) {
  const std::string body =
      "[[family]]\nfault = \"none\"\nperturb = { hull.mass_kg = { from = 1, to = 1e9, step = 1e-3 } }\n";
  EXPECT_NE(std::string::npos, error_of(spec_text(body)).find("'hull.mass_kg' makes more than 100000 values"));
  const std::string product =
      "[[family]]\nfault = \"none\"\nperturb = { hull.mass_kg = { from = 100, to = 599, step = 1 }, "
      "hull.drag_coeff = { from = 100, to = 599, step = 1 } }\n";
  const std::string over = error_of(spec_text(product));
  EXPECT_NE(std::string::npos, over.find("the spec makes 250000 cases, over the limit of 100000")) << over;
  std::string many = "[[family]]\nfault = \"none\"\n[family.perturb]\n";
  for (const char* k :
       {"hull.mass_kg", "hull.added_mass_kg", "hull.drag_coeff", "hull.buoyancy_n", "thrusters.max_n",
        "thrusters.lag_s", "depth_cell.noise_m", "filter.alpha", "filter.beta", "controller.gain_n", "yaw.lag_s",
        "yaw.drag_coeff", "surge.lag_s", "tank.width_y_m", "tank.length_x_m", "watchdog.silence_s", "sonar.noise"}) {
    many += std::string(k) + " = 0.5\n";
  }
  EXPECT_NE(std::string::npos, error_of(spec_text(many)).find("at most 16 may be perturbed together"));
}

TEST(CampaignSpec, BadTomlIsLocated) {
  EXPECT_EQ("c.toml:2:12: Error while parsing array", error_of(spec_text("seeds = [1,,2]\n")).substr(0, 38));
}

TEST(CampaignSpec, AnUnknownFaultKindIsLocatedAndNamesTheKnownOnes) {
  const std::string e = error_of(spec_text("[[family]]\nfault = \"leek\"\nat_s = 1\n"));
  EXPECT_NE(std::string::npos, e.find("c.toml:3:9: unknown fault kind 'leek'")) << e;
  EXPECT_NE(std::string::npos, e.find("weak_thrusters, leak, sensor_dropout, link_loss or none")) << e;
}

TEST(CampaignSpec, UnknownKeysAreLocatedEverywhere) {
  const std::string e = error_of(spec_text(R"(colour = "red"
[expect.default]
max_dept_m = 2
[[family]]
fault = "leak"
at_s = { from = 0, to = 2, stride = 1 }
helth = 0.5
)"));
  EXPECT_NE(std::string::npos, e.find("c.toml:2:1: unknown key 'colour'")) << e;
  EXPECT_NE(std::string::npos, e.find("c.toml:4:1: unknown expectation 'max_dept_m'")) << e;
  EXPECT_NE(std::string::npos, e.find("c.toml:7:28: unknown key 'stride' in 'at_s'")) << e;
  EXPECT_NE(std::string::npos, e.find("c.toml:8:1: unknown key 'helth' in a family")) << e;
}

TEST(CampaignSpec, ImpossibleRangesAreRefused) {
  const auto family = [](const std::string& at) {
    return spec_text("[[family]]\nfault = \"leak\"\nat_s = " + at + "\n");
  };
  EXPECT_NE(std::string::npos, error_of(family("{ from = 0, to = 5, step = -1 }"))
                                   .find("c.toml:4:35: 'at_s.step' must "
                                         "be a number > 0"));
  EXPECT_NE(std::string::npos,
            error_of(family("{ from = 0, to = 5, step = 0 }")).find("'at_s.step' must be a number > 0"));
  EXPECT_NE(std::string::npos, error_of(family("{ from = 5, to = 1, step = 1 }")).find("'at_s.to' (1) is below"));
  EXPECT_NE(std::string::npos, error_of(family("nan")).find("c.toml:4:8: 'at_s' must be in [0, 86400] (it is nan)"));
  EXPECT_NE(std::string::npos, error_of(family("{ from = 0, to = inf, step = 1 }")).find("'at_s.to' must be in"));
  EXPECT_NE(std::string::npos, error_of(family("-1")).find("'at_s' must be"));
  EXPECT_NE(std::string::npos, error_of(family("{ from = 0, to = 5, step = 1, sampled = 3 }")).find("exactly one of"));
  EXPECT_NE(std::string::npos, error_of(family("{ from = 0, to = 5, sampled = 0 }")).find("'at_s.sampled' must be"));
  EXPECT_NE(std::string::npos, error_of(family("[]")).find("must not be an empty list"));
  const std::string health = error_of(spec_text("[[family]]\nfault = \"weak_thrusters\"\nat_s = 1\nhealth = 1.5\n"));
  EXPECT_NE(std::string::npos, health.find("c.toml:5:10: 'health' must be in [0, 1] (it is 1.5)")) << health;
  EXPECT_NE(std::string::npos, error_of(spec_text("[[family]]\nfault = \"leak\"\nat_s = 1\nhealth = 0.5\n"))
                                   .find("'health' does not apply to a leak family"));
  EXPECT_NE(std::string::npos,
            error_of(spec_text("[[family]]\nfault = \"sensor_dropout\"\nat_s = 1\n")).find("needs 'duration_s'"));
}

TEST(CampaignSpec, AHugeGridIsRefusedBeforeAnythingIsMade) {
  const std::string e =
      error_of(spec_text("[[family]]\nfault = \"leak\"\nat_s = { from = 0, to = 1e4, step = 1e-300 }\n"));
  EXPECT_NE(std::string::npos, e.find("c.toml:4:37: 'at_s' makes more than 100000 values")) << e;
  // Axes within the limit whose product is over it: the count, and how to raise the limit.
  const std::string body =
      "seeds = { from = 0, count = 100 }\n[[family]]\nfault = \"weak_thrusters\"\n"
      "at_s = { from = 0, to = 99, step = 1 }\nhealth = { from = 0, to = 1, step = 0.01 }\n";
  const std::string over = error_of(spec_text(body));
  EXPECT_NE(std::string::npos, over.find("the spec makes 1010000 cases, over the limit of 100000 (--max-cases raises "
                                         "it)"))
      << over;
  auto raised = parse(spec_text(body), {2'000'000});
  ASSERT_TRUE(raised.ok()) << raised.error().message;
  EXPECT_EQ(1'010'000u, raised.value().case_count());
  EXPECT_EQ(1'009'999u, case_at(raised.value(), 1'009'999).index);
}

TEST(CampaignSpec, MissionsAreCheckedWhereTheSpecNamesThem) {
  TempDir dir;
  dir.write("own.coral", "// only needs to exist for the spec\n");
  const std::string ok = dir.write(
      "ok.toml",
      "missions = [\"own.coral\", \"../" +
          std::filesystem::relative(testing::kTankDir + "/tank.pl", std::filesystem::path(dir.path()).parent_path())
              .string() +
          "\"]\n[[family]]\nfault = \"none\"\n");
  auto spec = load_spec(ok);
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  EXPECT_EQ(dir.file("own.coral"), spec.value().missions[0].resolved);
  EXPECT_EQ(MissionKind::Prolog, spec.value().missions[1].kind);

  const std::string missing = dir.write("missing.toml", "missions = [\"nope.coral\"]\n[[family]]\nfault = \"none\"\n");
  auto bad = load_spec(missing);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(missing + ":1:13: mission 'nope.coral' not found (looked for " + dir.file("nope.coral") + ")",
            bad.error().message);
  EXPECT_NE(std::string::npos, error_of("missions = [\"tank.txt\"]\n[[family]]\nfault = \"none\"\n")
                                   .find("neither CORAL (.coral) nor PROLOG (.pl)"));
  EXPECT_NE(std::string::npos, error_of("[[family]]\nfault = \"none\"\n").find("missing 'missions'"));
}

TEST(CampaignSpec, ABoundIsAQuestionFromTheFaultAndItsErrorsAreLocated) {
  auto ok =
      parse(spec_text("[expect.leak]\nbound = \"fault system_problem -> exec surface\"\n[[family]]\nfault = "
                      "\"leak\"\nat_s = 3\nexpect = \"leak\"\n"));
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  const auto& bound = ok.value().expectations.at("leak").bound;
  ASSERT_TRUE(bound.has_value());
  EXPECT_EQ("system_problem", bound->from_name);
  EXPECT_EQ("surface", bound->to_name);
  const std::string e = error_of(spec_text(R"([expect.a]
bound = 3
[expect.b]
bound = "fault system_problem => exec surface"
[expect.c]
bound = "trip leak -> exec surface"
[expect.d]
bound = "fault system_problem -> surface within 30"
[[family]]
fault = "none"
expect = "a"
)"));
  EXPECT_NE(std::string::npos, e.find("c.toml:3:9: 'bound' must be a question in quotes")) << e;
  EXPECT_NE(std::string::npos, e.find("c.toml:5:9: 'bound': column 22: ")) << e;
  EXPECT_NE(std::string::npos, e.find("c.toml:7:9: 'bound' starts at the case's fault")) << e;
  EXPECT_EQ(std::string::npos, e.find("c.toml:9:")) << "a `within` is allowed (and not needed): " << e;
}

// A thousand expectation sets each asking its own bound would be a thousand
// analyses of every mission before the first case: at most kMaxBounds
// distinct questions; the same question again costs nothing.
TEST(CampaignSpec, AThousandDistinctBoundsAreRefusedAtTheFirstPastTheLimit) {
  std::string sets, same;
  for (int i = 0; i < 1000; ++i) {
    sets += fmt::format("[expect.s{}]\nbound = \"fault system_problem -> exec surface within {}\"\n", i, i + 1);
    same += fmt::format("[expect.s{}]\nbound = \"fault system_problem -> exec surface\"\n", i);
  }
  const std::string family = "[[family]]\nfault = \"leak\"\nat_s = 3\nexpect = \"s0\"\n";
  const std::string e = error_of(spec_text(sets + family));
  EXPECT_NE(std::string::npos, e.find("more than 16 different bounds in one spec")) << e.substr(0, 400);
  EXPECT_EQ(e.find("different bounds"), e.rfind("different bounds")) << "said once";
  auto ok = parse(spec_text(same + family));
  EXPECT_TRUE(ok.ok()) << (ok ? "" : ok.error().message.substr(0, 400));
}

TEST(CampaignSpec, ExpectationsAreCheckedAndFamiliesMustNameOne) {
  const std::string e = error_of(spec_text(R"([expect.strict]
outcomes = ["completed", "won"]
surface_within_s = -1
no_stall = "yes"
[[family]]
fault = "none"
expect = "lenient"
)"));
  EXPECT_NE(std::string::npos, e.find("c.toml:3:26: an outcome is one of")) << e;
  EXPECT_NE(std::string::npos, e.find("c.toml:4:20: 'surface_within_s' must be a number >= 0")) << e;
  EXPECT_NE(std::string::npos, e.find("c.toml:5:12: 'no_stall' must be true or false")) << e;
  EXPECT_NE(std::string::npos, e.find("c.toml:8:10: no [expect.lenient] in this spec")) << e;
  EXPECT_NE(
      std::string::npos,
      error_of(spec_text("[[family]]\nfault = \"none\"\n[[family]]\nfault = \"none\"\n")).find("a second family"));
}

TEST(CampaignSpec, TopLevelLimitsAreBounded) {
  const std::string family = "[[family]]\nfault = \"none\"\n";
  EXPECT_NE(std::string::npos,
            error_of(spec_text("telemetry_hz = 0\n" + family)).find("c.toml:2:16: 'telemetry_hz' must"));
  EXPECT_NE(std::string::npos, error_of(spec_text("max_sim_time_s = 1e9\n" + family)).find("'max_sim_time_s' must"));
  EXPECT_NE(std::string::npos, error_of(spec_text("sample_seed = -1\n" + family)).find("'sample_seed' must"));
  EXPECT_NE(std::string::npos, error_of(spec_text("seeds = { from = 1, count = 0 }\n" + family)).find("'seeds.count'"));
  auto ok = parse(spec_text("telemetry_hz = 2\nmax_sim_time_s = 60\n" + family));
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  EXPECT_EQ(2.0, ok.value().telemetry_hz);
  EXPECT_EQ(60.0, ok.value().max_sim_time_s);
}

TEST(CampaignSpec, IndexRangesStayInsideTheCampaign) {
  auto r = parse_range("3-7", 10);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(3u, r.value().first);
  EXPECT_EQ(7u, r.value().last);
  EXPECT_TRUE(parse_range("9", 10).ok());
  EXPECT_EQ("'10' is outside the campaign's cases 0-9", parse_range("10", 10).error().message);
  EXPECT_FALSE(parse_range("7-3", 10).ok());
  EXPECT_FALSE(parse_range("a-b", 10).ok());
  EXPECT_FALSE(parse_range("-3", 10).ok());
}

}  // namespace
}  // namespace strata::campaign
