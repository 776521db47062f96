// The files a campaign spec names for every case (spec_files.h): `params`,
// the vehicle's parameter file, and `world`, a scenario's world; each read
// when the spec is, its problems located at the key (and in the file).
#include "campaign/spec_files.h"

#include <gtest/gtest.h>

#include "campaign/campaign_test_support.h"
#include "campaign/cases.h"
#include "campaign/spec.h"
#include "core/test_fifo.h"

namespace strata::campaign {
namespace {

using testing::error_of;
using testing::parse;
using testing::spec_text;
using testing::TempDir;

// Issue 21: perturbations started from the built-in parameters only; a
// spec's `params` file is now the vehicle every case starts from.
TEST(CampaignSpec, ASpecsParameterFileIsTheVehicleItsPerturbationsStartFrom) {
  TempDir dir;
  vehicle::VehicleParams heavy = vehicle::default_params();
  heavy.mass_kg = 190.0;
  dir.write("heavy.toml", vehicle::params_toml(heavy));
  auto spec = load_spec(dir.write("c.toml", spec_text(R"(params = "heavy.toml"
[[family]]
fault = "none"
perturb = { thrusters.max_n = [15, 18] }
)")));
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  const Spec& s = spec.value();
  EXPECT_EQ("heavy.toml", s.params);
  EXPECT_EQ(dir.file("heavy.toml"), s.params_resolved);
  const Case c = case_at(s, 1);
  EXPECT_EQ(190.0, case_params(s, c).mass_kg) << "the file's value, not the built-in one";
  EXPECT_EQ(18.0, case_params(s, c).thruster_max_n);
}

TEST(CampaignSpec, ABadParameterFileIsTheSpecsErrorAtItsKey) {
  TempDir dir;
  dir.write("bad.toml", "[hull]\nmass_kg = -3\n");
  auto bad = load_spec(dir.write("c.toml", spec_text("params = \"bad.toml\"\n")));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(std::string::npos, bad.error().message.find("c.toml:2:10: 'params': ")) << bad.error().message;
  EXPECT_NE(std::string::npos, bad.error().message.find("mass_kg")) << bad.error().message;
  auto missing = load_spec(dir.write("m.toml", spec_text("params = \"nosuch.toml\"\n")));
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(std::string::npos, missing.error().message.find("m.toml:2:10: 'params': ")) << missing.error().message;
  EXPECT_NE(std::string::npos, error_of(spec_text("params = 3\n")).find("'params' must name a vehicle parameter file"));
  // What is not a regular file is refused at once, not read (a FIFO would block for ever).
  auto folder = load_spec(dir.write("d.toml", spec_text("params = \".\"\n")));
  ASSERT_FALSE(folder.ok());
  EXPECT_NE(std::string::npos, folder.error().message.find("d.toml:2:10: 'params': ")) << folder.error().message;
  const auto fifo = core::testing::make_fifo("params.toml");
  ASSERT_FALSE(fifo.empty());
  auto piped = load_spec(dir.write("f.toml", spec_text("params = \"" + fifo.string() + "\"\n")));
  std::filesystem::remove_all(fifo.parent_path());
  ASSERT_FALSE(piped.ok());
  EXPECT_NE(std::string::npos, piped.error().message.find("f.toml:2:10: 'params': ")) << piped.error().message;
}

// world = "FILE": an open-water mission's campaign runs every case in the
// world of a scenario file (its [world], [seabed] and [vehicle]; the seed and
// the faults stay the campaign's).
TEST(CampaignSpec, AWorldFileGivesEveryCaseItsWorldAndAFaultInItIsRefused) {
  TempDir dir;
  dir.write("sea.toml",
            "seed = 11\n[world]\nkind = \"open_water\"\ncurrent_y_mps = 0.1\n[seabed]\nkind = "
            "\"flat\"\ndepth_m = 25.0\n[vehicle]\nheading_deg = 90.0\n");
  auto spec =
      load_spec(dir.write("c.toml", spec_text("world = \"sea.toml\"\n") + "[[family]]\nfault = \"leak\"\nat_s = 30\n"));
  ASSERT_TRUE(spec.ok()) << spec.error().message;
  const Case c = case_at(spec.value(), 0);
  auto scenario = vehicle::parse_scenario(scenario_toml(spec.value(), c), "case.toml");
  ASSERT_TRUE(scenario.ok()) << scenario.error().message << "\n" << scenario_toml(spec.value(), c);
  EXPECT_TRUE(scenario.value().world.open_water);
  EXPECT_DOUBLE_EQ(0.1, scenario.value().world.current_y_mps);
  EXPECT_DOUBLE_EQ(90.0, scenario.value().vehicle_heading_deg);
  ASSERT_EQ(1u, scenario.value().faults.size());  // the family's, not the file's
  EXPECT_EQ(c.seed, scenario.value().seed);
  // Its faults are the families' to give; other errors at the key too.
  dir.write("faulty.toml", "[world]\nkind = \"open_water\"\n[[fault]]\nkind = \"leak\"\nat_s = 5\n");
  auto faulty =
      load_spec(dir.write("f.toml", spec_text("world = \"faulty.toml\"\n") + "[[family]]\nfault = \"none\"\n"));
  ASSERT_FALSE(faulty.ok());
  EXPECT_NE(std::string::npos, faulty.error().message.find("f.toml:2:9: 'world': faulty.toml has 'fault'"))
      << faulty.error().message;
  dir.write("bad.toml", "[world]\nkind = \"lake\"\n");
  auto bad = load_spec(dir.write("b.toml", spec_text("world = \"bad.toml\"\n")));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(std::string::npos, bad.error().message.find("b.toml:2:9: 'world': ")) << bad.error().message;
  // At the world file's own line and column, not the text made from it.
  EXPECT_NE(std::string::npos, bad.error().message.find("bad.toml:2:8: 'world.kind'")) << bad.error().message;
  dir.write("late.toml", "# a lake\n\n[world]\nkind = \"open_water\"\ncurrent_y_mps = \"fast\"\n");
  auto late = load_spec(dir.write("l.toml", spec_text("world = \"late.toml\"\n")));
  ASSERT_FALSE(late.ok());
  EXPECT_NE(std::string::npos, late.error().message.find("late.toml:5:17: 'world.current_y_mps' must be a number"))
      << late.error().message;
  auto missing = load_spec(dir.write("m.toml", spec_text("world = \"nosuch.toml\"\n")));
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(std::string::npos, missing.error().message.find("m.toml:2:9: 'world': ")) << missing.error().message;
  // Not TOML: the place in the world file too.
  dir.write("garbled.toml", "[world]\nkind = = \"open_water\"\n");
  auto garbled = load_spec(dir.write("g.toml", spec_text("world = \"garbled.toml\"\n")));
  ASSERT_FALSE(garbled.ok());
  EXPECT_NE(std::string::npos, garbled.error().message.find("garbled.toml:2:")) << garbled.error().message;
  EXPECT_NE(std::string::npos, error_of(spec_text("world = 3\n")).find("'world' must name a scenario file"));
  const auto fifo = core::testing::make_fifo("world.toml");
  ASSERT_FALSE(fifo.empty());
  auto piped = load_spec(dir.write("p.toml", spec_text("world = \"" + fifo.string() + "\"\n")));
  std::filesystem::remove_all(fifo.parent_path());
  ASSERT_FALSE(piped.ok());
  EXPECT_NE(std::string::npos, piped.error().message.find("p.toml:2:9: 'world': ")) << piped.error().message;
}

// Hostile `params` and `world` values: each is the spec's error at its key
// (line 2: the key's value starts at column 10 or 9), read at once or not at
// all, never waited on.
constexpr const char* kNoFault = "[[family]]\nfault = \"none\"\n";

TEST(CampaignSpec, WhatAParamsOrWorldKeyNamesIsRefusedAtTheKeyUnlessAPlainFile) {
  TempDir dir;
  auto refused_at = [&](const std::string& key, const std::string& value, const std::string& more = "") {
    auto spec = load_spec(dir.write("s.toml", spec_text(key + " = " + value + "\n") + kNoFault));
    if (spec.ok()) return std::string("accepted: ") + key + " = " + value;
    const std::string at = "s.toml:2:" + std::string(key == "params" ? "10" : "9") + ": ";
    const std::string& m = spec.error().message;
    if (m.find(at) == std::string::npos) return "not at " + at + ": " + m;
    if (!more.empty() && m.find(more) == std::string::npos) return "no '" + more + "' in: " + m;
    return std::string("ok");
  };
  std::filesystem::create_directory(dir.file("folder"));
  std::filesystem::create_symlink("loop.toml", dir.file("loop.toml"));
  std::filesystem::create_symlink("folder", dir.file("to_folder.toml"));
  for (const std::string key : {"params", "world"}) {
    SCOPED_TRACE(key);
    EXPECT_EQ("ok", refused_at(key, "\"folder\""));
    EXPECT_EQ("ok", refused_at(key, "\"to_folder.toml\""));
    EXPECT_EQ("ok", refused_at(key, "\"loop.toml\""));
    EXPECT_EQ("ok", refused_at(key, "\"/dev/zero\""));
    EXPECT_EQ("ok", refused_at(key, "\"/dev/urandom\""));
    EXPECT_EQ("ok", refused_at(key, "\"\"", "must name"));
    EXPECT_EQ("ok", refused_at(key, "[\"a.toml\"]", "must name"));
    EXPECT_EQ("ok", refused_at(key, "{ file = \"a.toml\" }", "must name"));
    EXPECT_EQ("ok", refused_at(key, "true", "must name"));
    EXPECT_EQ("ok", refused_at(key, "\"../../../../../../../../nosuch.toml\""));
  }
  // Over the limit: refused by its size, not read to the end.
  dir.write("big.toml", "[world]\nkind = \"open_water\"\n#" + std::string(std::size_t{1} << 20, 'x') + "\n");
  EXPECT_EQ("ok", refused_at("world", "\"big.toml\"", "over the limit"));
  // Not UTF-8: the world file's own place too.
  dir.write("latin1.toml", "[world]\nkind = \"open\xe9water\"\n");
  EXPECT_EQ("ok", refused_at("world", "\"latin1.toml\"", "latin1.toml:2:"));
  dir.write("latin1p.toml", "[hull]\nmass_kg = 3 # \xff\xfe\n");
  EXPECT_EQ("ok", refused_at("params", "\"latin1p.toml\""));
  // A world file's faults are the families' (an array of tables or not).
  dir.write("faults.toml", "[world]\nkind = \"open_water\"\nfault = []\n");
  EXPECT_EQ("ok", refused_at("world", "\"faults.toml\""));
  dir.write("fault.toml", "[[fault]]\nkind = \"leak\"\nat_s = 5\n");
  EXPECT_EQ("ok", refused_at("world", "\"fault.toml\"", "has 'fault'"));
  // A huge table in the world: refused as unknown, at the key, without
  // naming every entry.
  std::string huge = "[world]\nkind = \"open_water\"\n";
  for (int i = 0; i < 20000; ++i) huge += "k" + std::to_string(i) + " = " + std::to_string(i) + "\n";
  dir.write("huge.toml", huge);
  EXPECT_EQ("ok", refused_at("world", "\"huge.toml\""));
}

// A world file is a scenario file whose seed the campaign replaces: a seed
// that no scenario would take is still the file's error, not dropped unread.
TEST(CampaignSpec, AWorldFilesSeedOfTheWrongTypeIsRefusedAtTheKey) {
  TempDir dir;
  dir.write("sea.toml", "seed = \"eleven\"\n[world]\nkind = \"open_water\"\n");
  EXPECT_FALSE(vehicle::parse_scenario("seed = \"eleven\"\n[world]\nkind = \"open_water\"\n", "sea.toml").ok())
      << "a scenario refuses it";
  auto spec = load_spec(dir.write("c.toml", spec_text("world = \"sea.toml\"\n") + kNoFault));
  ASSERT_FALSE(spec.ok()) << "a world file's string seed was accepted";
  EXPECT_NE(std::string::npos, spec.error().message.find("c.toml:2:9: 'world': ")) << spec.error().message;
  EXPECT_NE(std::string::npos, spec.error().message.find("seed")) << spec.error().message;
  dir.write("ok.toml", "seed = 11\ndescription = \"the sea\"\n[world]\nkind = \"open_water\"\n");
  auto ok = load_spec(dir.write("d.toml", spec_text("world = \"ok.toml\"\n") + kNoFault));
  EXPECT_TRUE(ok.ok()) << ok.error().message;
}

// A world file's errors were located in the text the campaign rewrote from
// it (its tables re-printed after a "seed = 0" line), not in the file: a bad
// value on line 6 was reported on line 3.
TEST(CampaignSpec, AWorldFilesErrorIsLocatedInTheFileAsWritten) {
  TempDir dir;
  dir.write(
      "sea.toml",
      "# The sea off the pier.\n\ndescription = \"calm\"\n[world]\nkind = \"open_water\"\ncurrent_y_mps = \"fast\"\n");
  auto spec = load_spec(dir.write("c.toml", spec_text("world = \"sea.toml\"\n") + kNoFault));
  ASSERT_FALSE(spec.ok());
  EXPECT_NE(std::string::npos, spec.error().message.find("c.toml:2:9: 'world': " + dir.file("sea.toml") + ":6:"))
      << spec.error().message;
}

// "sea.toml\u0000junk" opened sea.toml (the system's calls end a name at
// the NUL) and was kept as the spec's world, NUL and all.
TEST(CampaignSpec, AFileNameWithANulIsRefusedNotCutShort) {
  TempDir dir;
  dir.write("sea.toml", "[world]\nkind = \"open_water\"\n");
  auto world = load_spec(dir.write("c.toml", spec_text(R"(world = "sea.toml\u0000junk")"
                                                       "\n") +
                                                 kNoFault));
  ASSERT_FALSE(world.ok()) << "accepted as " << world.value().world;
  EXPECT_NE(std::string::npos, world.error().message.find("c.toml:2:9: 'world': a file name cannot hold a NUL"))
      << world.error().message;
  auto params = load_spec(dir.write("p.toml", spec_text(R"(params = "\u0000")"
                                                        "\n") +
                                                  kNoFault));
  ASSERT_FALSE(params.ok());
  EXPECT_EQ(std::string::npos, params.error().message.find('\0')) << "the NUL itself printed";
}

}  // namespace
}  // namespace strata::campaign
