// Literal numbers in PROLOG primitive calls against the catalogue's ranges
// (issue 20): the scan of the rule text, and what `strata check` reports.
#include "strategic/prolog_rules_args.h"

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "strategic/prolog_mission.h"
#include "strategic/prolog_mission_test_support.h"

namespace strata::strategic {
namespace {

using prolog_mission_testing::PrologMissionTest;

std::vector<std::string> found(std::string_view text) {
  std::vector<std::string> out;
  for (const auto& p : scan_primitive_arguments(text, tactical::Catalogue::builtin())) {
    out.push_back(std::to_string(p.line) + ":" + std::to_string(p.column) + " " + p.text);
  }
  return out;
}

TEST(RulesArguments, NumbersOutOfRangeAreFoundWithTheirPlace) {
  EXPECT_EQ((std::vector<std::string>{
                "2:36 exec_heading/2: 'heading' argument 'degrees' is 400, above the maximum 360 deg",
                "3:16 exec_sleep/2: 'sleep' argument 'seconds' is 0.01, below the minimum 0.1 s",
                "5:5 exec_heading/2: 'heading' argument 'degrees' is -1, below the minimum 0 deg",
            }),
            found("mission :-\n"
                  "    exec_sleep(1, _), exec_heading(400, X),\n"
                  "    exec_sleep(0.01, X),\n"
                  "    exec_heading(\n"
                  "    -1, _).\n"));
}

TEST(RulesArguments, HugeNumbersAreNotFinite) {
  const std::string digits(400, '9');
  EXPECT_EQ((std::vector<std::string>{
                "1:23 exec_sleep/2: 'sleep' argument 'seconds' is 1.0e999, which is not a "
                "finite number",
                "1:47 exec_sleep/2: 'sleep' argument 'seconds' is " + digits + ", which is not a finite number"}),
            found("mission :- exec_sleep(1.0e999, _), exec_sleep(" + digits + ", _)."));
}

TEST(RulesArguments, WhatIsNotALiteralNumberInACallIsLeftAlone) {
  EXPECT_TRUE(found("% exec_heading(400, X) in a comment\n"
                    "/* exec_heading(400, X) */\n"
                    "m :- atom_length('exec_heading(400, X)', _), S = \"exec_sleep(0, X)\",\n"
                    "     D is 400, exec_heading(D, _), exec_heading(400 - 60, _),\n"
                    "     exec_heading(360, _), exec_sleep(3600, _), exec_sleep(0.1, _),\n"
                    "     my_exec_heading(400, _), exec_heading(400), exec_heading(1, 2, 3),\n"
                    "     exec_no_such_primitive(400, _), ask_heading(400, _), exec_heading(400, _\n")
                  .empty());
}

TEST(RulesArguments, ACallInsideAnotherCallsArgumentsIsChecked) {
  EXPECT_EQ((std::vector<std::string>{"1:30 exec_heading/2: 'heading' argument 'degrees' is 361, above the maximum "
                                      "360 deg"}),
            found("m :- findall(X, exec_heading(361, X), _)."));
}

TEST_F(PrologMissionTest, check_reports_a_literal_out_of_range_with_its_place) {
  const std::string path = rules_.write("m.pl",
                                        "mission :-\n"
                                        "    exec_heading(400, X),\n"
                                        "    X == 1.\n");
  prolog_mission_testing::Reported messages;
  auto m = PrologMission::load(path, tactical::Catalogue::builtin(), messages.sources, messages.sink);
  EXPECT_FALSE(m.ok());
  ASSERT_EQ(1u, messages.size());
  EXPECT_EQ(path +
                ":2:18: error: exec_heading/2: 'heading' argument 'degrees' is 400, above the maximum 360 deg "
                "[ArgumentOutOfRange]",
            messages.headline(0));
}

std::vector<std::string> unavailable_on_imc(std::string_view text) {
  std::vector<std::string> out;
  for (const auto& p :
       scan_unavailable_primitives(text, tactical::Catalogue::builtin(), tactical::ExecutionLevel::Imc)) {
    out.push_back(std::to_string(p.line) + ":" + std::to_string(p.column) + " " + p.text);
  }
  return out;
}

TEST(RulesExecutionLevel, CallsAnImcVehicleCannotCarryOutAreFoundAtTheirName) {
  // What an IMC vehicle carries (the sonar's start and stop, position_uncertain, heading, sleep, the plan's start)
  // is left alone.
  EXPECT_EQ((std::vector<std::string>{
                "2:5 'target_detected' is not available on an IMC vehicle: an IMC vehicle sends no sonar sweeps on "
                "this link (the Phoenix's sonar socket has no IMC counterpart)",
                "4:24 'set_sway' is not available on an IMC vehicle: an IMC vehicle takes no sideways speed (a "
                "Reference has none)",
            }),
            unavailable_on_imc("mission :-\n"
                               "    ask_target_detected(X), exec_heading(90, X), exec_start_sonar(_),\n"
                               "    exec_sleep(1, _), ask_position_uncertain(_), ood('start_network', _),\n"
                               "    findall(Y, (X = 1, exec_set_sway(0.1, Y)), _), exec_stop_sonar(_).\n"));
}

TEST(RulesExecutionLevel, WhatIsNoCallOfAPrimitiveIsLeftAlone) {
  EXPECT_TRUE(unavailable_on_imc("% ask_target_detected(X) in a comment\n"
                                 "/* exec_set_sway(0.1, X) */\n"
                                 "m :- atom_length('ask_target_detected(X)', _), S = \"exec_set_sway(0.1, X)\",\n"
                                 "     my_ask_target_detected(_), ask_target_detected, ask_set_sway(_),\n"
                                 "     exec_target_detected(_), exec_heading(1, _).\n")
                  .empty());
  EXPECT_TRUE(scan_unavailable_primitives("m :- ask_target_detected(_), exec_set_sway(0.1, _).",
                                          tactical::Catalogue::builtin(), tactical::ExecutionLevel::Phoenix)
                  .empty());
}

TEST_F(PrologMissionTest, check_for_an_imc_vehicle_refuses_calls_at_their_place_in_every_file) {
  rules_.write("search.pl",
               "% the search, consulted: the sonar's start passes, set_sway is refused\n"
               "search(X) :-\n"
               "    exec_heading(90, X), exec_set_sway(0.1, X), exec_start_sonar(X).\n");
  const std::string path = rules_.write("m.pl",
                                        ":- consult(search).\n"
                                        "mission :-\n"
                                        "    search(X),\n"
                                        "    ask_target_detected(X).\n");
  prolog_mission_testing::Reported messages;
  auto m = PrologMission::load(path, tactical::Catalogue::builtin(), messages.sources, messages.sink, {}, KeepRules::No,
                               tactical::ExecutionLevel::Imc);
  EXPECT_FALSE(m.ok());
  std::vector<std::string> got;
  for (std::size_t i = 0; i < messages.size(); ++i) {
    const core::Diagnostic& message = messages[i];
    EXPECT_EQ(core::DiagnosticKind::PrimitiveUnavailable, message.kind);
    got.push_back(std::filesystem::path(messages.file(i)).filename().string() + ":" +
                  std::to_string(messages.place(i).line) + ":" + std::to_string(messages.place(i).col) + " " +
                  message.message.substr(0, message.message.find(':')));
  }
  std::sort(got.begin(), got.end());
  EXPECT_EQ((std::vector<std::string>{"m.pl:4:5 'target_detected' is not available on an IMC vehicle",
                                      "search.pl:3:26 'set_sway' is not available on an IMC vehicle"}),
            got);
  // The same rules for the Phoenix protocol (the default): clean.
  prolog_mission_testing::Reported phoenix;
  EXPECT_TRUE(PrologMission::load(path, tactical::Catalogue::builtin(), phoenix.sources, phoenix.sink).ok());
  EXPECT_TRUE(phoenix.empty()) << phoenix.text();
}

// Regression: the files a mission's files include/1 (at any depth) were
// not scanned, so a call there that an IMC vehicle cannot carry out passed
// the check and failed in the water.
TEST_F(PrologMissionTest, check_for_an_imc_vehicle_refuses_calls_in_an_included_file) {
  rules_.write("deeper.pl", "p(X) :-\n    exec_set_sway(0.1, X).\n");
  rules_.write("search.pl", ":- include(deeper).\n");
  const std::string path = rules_.write("m.pl", ":- include(search).\nmission :- p(_).\n");
  prolog_mission_testing::Reported messages;
  auto m = PrologMission::load(path, tactical::Catalogue::builtin(), messages.sources, messages.sink, {}, KeepRules::No,
                               tactical::ExecutionLevel::Imc);
  EXPECT_FALSE(m.ok());
  ASSERT_EQ(messages.size(), 1U) << messages.text();
  EXPECT_EQ(core::DiagnosticKind::PrimitiveUnavailable, messages[0].kind);
  EXPECT_EQ("deeper.pl", std::filesystem::path(messages.file(0)).filename().string());
  EXPECT_EQ(2U, messages.place(0).line);
  EXPECT_EQ(5U, messages.place(0).col);
}

}  // namespace
}  // namespace strata::strategic
