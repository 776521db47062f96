// Literal numbers in PROLOG primitive calls against the catalogue's ranges
// (issue 20): the scan of the rule text, and what `strata check` reports.
#include "strategic/prolog_rules_args.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "strategic/prolog_mission.h"
#include "strategic/prolog_mission_test_support.h"

namespace strata::prolog {
namespace {

using testing_support::PrologMission;

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

TEST_F(PrologMission, check_reports_a_literal_out_of_range_with_its_place) {
  const std::string path = rules_.write("m.pl",
                                        "mission :-\n"
                                        "    exec_heading(400, X),\n"
                                        "    X == 1.\n");
  std::vector<Message> messages;
  auto m = Mission::load(path, tactical::Catalogue::builtin(), messages);
  EXPECT_FALSE(m.ok());
  ASSERT_EQ(1u, messages.size());
  EXPECT_EQ(path +
                ":2:18: error: exec_heading/2: 'heading' argument 'degrees' is 400, above the maximum 360 deg "
                "[ArgumentOutOfRange]",
            format_message(messages[0]));
}

}  // namespace
}  // namespace strata::prolog
