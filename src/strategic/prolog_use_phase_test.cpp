// `:- use_phase(Name).`: a phase of Strata's library (library/prolog/,
// docs/library.md) loaded into the mission's module, and the names it
// refuses, at the directive.
#include "strategic/prolog_mission_test_support.h"

namespace strata::strategic::prolog_mission_testing {
namespace {

TEST_F(PrologMissionTest, UsePhaseLoadsTheLibrarysPhaseIntoTheMission) {
  auto m = load_ok(rules_.write("m.pl", R"(
:- use_phase(goto).
:- use_phase(goto).
mission :- goto(1, 2, 3, 0.5, Exit), report(Exit).
)"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  host.answers = {1, 1, 1, 1, 0, 1, 1};  // waypoint_reached: 0, then 1
  PrologMissionQuery q(*m, host, 100000);
  const auto s = run(q);
  EXPECT_TRUE(s == prolog::Query::Status::True || s == prolog::Query::Status::Last) << q.exception_text();
  q.close();
  EXPECT_EQ(
      (std::vector<std::string>{"call goto_depth 3", "call set_speed 0.5", "call goto_xy 1 2", "call sleep 1",
                                "call waypoint_reached", "call sleep 1", "call waypoint_reached", "report arrived"}),
      host.events);
  EXPECT_EQ(RulesOutcome::Completed, mission_outcome(*m).value());
}

TEST_F(PrologMissionTest, UsePhaseOfANameTheLibraryLacksIsAnErrorAtTheDirective) {
  Reported reported;
  auto m = PrologMission::load(rules_.write("m.pl", "mission :- true.\n\n:- use_phase(no_such_phase).\n"),
                               tactical::Catalogue::builtin(), reported.sources, reported.sink);
  EXPECT_FALSE(m);
  ASSERT_EQ(1u, reported.size()) << reported.text();
  EXPECT_EQ(core::DiagnosticKind::PrologLoadError, reported[0].kind);
  EXPECT_EQ(3u, reported.place(0).line);
  EXPECT_NE(std::string::npos, reported[0].message.find("no library phase `no_such_phase`: no_such_phase.pl is in "
                                                        "none of the library's folders ("))
      << reported.text();
  EXPECT_NE(std::string::npos, reported[0].message.find("library/prolog)")) << reported.text();
}

TEST_F(PrologMissionTest, UsePhaseTakesAPlainNameNotAPath) {
  for (const char* name : {"'../tank/phases'", "'/etc/passwd'", "_", "goto(1)", "''"}) {
    Reported reported;
    auto m = PrologMission::load(rules_.write("m.pl", "mission :- true.\n:- use_phase(" + std::string(name) + ").\n"),
                                 tactical::Catalogue::builtin(), reported.sources, reported.sink);
    EXPECT_FALSE(m) << name;
    ASSERT_EQ(1u, reported.size()) << name << ": " << reported.text();
    EXPECT_EQ(2u, reported.place(0).line) << name;
    EXPECT_NE(std::string::npos, reported[0].message.find("a library phase is named by a plain name"))
        << name << ": " << reported.text();
  }
}

}  // namespace
}  // namespace strata::strategic::prolog_mission_testing
