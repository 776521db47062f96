// A verifier witness as the vehicle answers its path needs (witness.h).
#include "coral/witness.h"

#include <gtest/gtest.h>

#include "coral/test_support.h"
#include "coral/verify_question.h"

namespace strata::coral {
namespace {

using testing::compile_text;

// tests/verify/stuck_phase.coral: when the depth is not reached the phase stalls.
constexpr const char* kStuck =
    "net stuck { place start = 1, setpoint_read, monitoring, reached, not_reached; exit complete, abort;\n"
    "  transition read_setpoint { wait { start } action { TACTIC(EXEC, next_setpt_data, setpoint_read) } }\n"
    "  transition wait_a_second { wait { setpoint_read } action { TACTIC(EXEC, sleep(1), monitoring) } }\n"
    "  transition check_depth { wait { monitoring } action { TACTIC(ASK, depth_reached, reached, not_reached) } }\n"
    "  transition depth_ok { wait { reached } signal { complete } } }\n";

std::string summary(const nlohmann::ordered_json& answers) {
  std::string out;
  for (const auto& a : answers) {
    out += (out.empty() ? "" : " ") + a.at("transition").get<std::string>() + ":" + a.at("action").get<std::string>() +
           ":" + a.at("primitive").get<std::string>() + "=" + a.at("answer").dump() + "@" + a.at("step").dump();
  }
  return out;
}

TEST(Witness, AStallCounterexampleGivesTheAnswersOfItsPath) {
  auto c = compile_text(kStuck);
  ASSERT_TRUE(c->program);
  const VerifyReport report = verify_program(*c->program);
  const Property* deadlock = nullptr;
  for (const auto& p : report.nets.at(0).properties) {
    if (p.key == "no_deadlock") deadlock = &p;
  }
  ASSERT_TRUE(deadlock && deadlock->counterexample);
  auto j = witness_answers_json("stuck.coral", "stuck", "no_deadlock counterexample", deadlock->counterexample->steps);
  EXPECT_EQ(1, j.at("strata_answers"));
  EXPECT_EQ("stuck", j.at("net"));
  EXPECT_EQ("read_setpoint:exec:next_setpt_data=1@2 wait_a_second:exec:sleep=1@4 check_depth:ask:depth_reached=0@6",
            summary(j.at("answers")));
  ASSERT_EQ(6u, j.at("path").size());
  EXPECT_EQ("6. ASK depth_reached (check_depth) answers 0 -> not_reached", j.at("path")[5]);
  EXPECT_EQ(3u, answer_count(deadlock->counterexample->steps));
}

TraceStep fire(std::string t, std::vector<std::string> actions) {
  TraceStep s;
  s.transition = std::move(t);
  s.actions = std::move(actions);
  return s;
}
TraceStep answer(std::string t, std::string action, std::string tactic, std::string primitive, std::string value) {
  TraceStep s;
  s.kind = TraceStep::Kind::Answer;
  s.transition = std::move(t);
  s.action = std::move(action);
  s.tactic = std::move(tactic);
  s.primitive = std::move(primitive);
  s.answer = std::move(value);
  return s;
}

// Calls in flight together may be answered in any order on a path; a run
// meets them in the order they were called.
TEST(Witness, AnswersAreInTheOrderTheirCallsWereIssued) {
  std::vector<TraceStep> steps{
      fire("both", {"EXEC start_timer", "ASK time_out"}),                 // 1
      fire("other", {"ASK depth_reached"}),                               // 2
      answer("other", "ASK depth_reached", "ask", "depth_reached", "1"),  // 3
      answer("both", "ASK time_out", "ask", "time_out", "0"),             // 4
      fire("both", {"EXEC start_timer", "ASK time_out"}),                 // 5
      answer("both", "ASK time_out", "ask", "time_out", "1"),             // 6: the second firing's
      answer("both", "EXEC start_timer", "exec", "start_timer", "1"),     // 7: the first firing's
      answer("both", "EXEC start_timer", "exec", "start_timer", "1"),     // 8: the second's
  };
  auto j = witness_answers_json("m.coral", "n", "test", steps);
  EXPECT_EQ(
      "both:exec:start_timer=1@7 both:ask:time_out=0@4 other:ask:depth_reached=1@3 both:exec:start_timer=1@8 "
      "both:ask:time_out=1@6",
      summary(j.at("answers")));
}

TEST(Witness, APhaseAnswerNamesTheExitItEndsAt) {
  auto c = compile_text(
      "net p { place s = 1, a, b; exit done, failed;\n"
      "  transition ask { wait { s } action { TACTIC(ASK, depth_reached, a, b) } }\n"
      "  transition yes { wait { a } signal { done } }\n"
      "  transition no { wait { b } signal { failed } } }\n"
      "mission m { place begin = 1, ok, bad; exit fine, sad;\n"
      "  transition go { wait { begin } action { PHASE(p, ok, bad) } }\n"
      "  transition good { wait { ok } signal { fine } }\n"
      "  transition poor { wait { bad } signal { sad } } }\n");
  ASSERT_TRUE(c->program);
  auto an = question_analysis_net(*c->program, "", {});
  ASSERT_TRUE(an.ok());
  const petri::Net& net = an.value().net;
  std::vector<petri::TransitionId> path{*net.find_transition("go"), *net.find_transition("go.p.failed"),
                                        *net.find_transition("poor")};
  const auto steps = trace_of(*c->program, an.value(), path);
  auto j = witness_answers_json("m.coral", "m", "question", steps);
  EXPECT_EQ("go:phase:p=\"failed\"@2", summary(j.at("answers")));
  EXPECT_EQ("3. fire poor -> sad", j.at("path")[2]);
}

}  // namespace
}  // namespace strata::coral
