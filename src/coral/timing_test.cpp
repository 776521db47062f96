// The timing analysis (coral/timing.h) on small hand-made missions whose
// worst and best cases are known by hand: a sequence, a choice, two calls
// at once, a polling loop (with and without a guard), a nested phase, the
// fault itself, and the questions' syntax.
#include "coral/timing.h"

#include <algorithm>

#include <gtest/gtest.h>

#include "coral/test_support.h"
#include "coral/verifier.h"

namespace strata::coral {
namespace {

// Every primitive answers within 0.1 s; sleep after its argument first.
BoundOptions options() {
  BoundOptions o;
  o.primitive = [](std::string_view name) -> std::optional<PrimitiveTiming> {
    PrimitiveTiming t;
    t.reply_s = 0.1;
    if (name == "sleep") {
      t.wait_arg = 0;
      t.wait_arg_max = 3600;
    }
    return t;
  };
  return o;
}

BoundAnswer bound(const std::string& text, const std::string& question) {
  auto c = testing::compile_text(text);
  if (!c->program) {
    std::string all;
    for (const auto& k : c->kinds()) all += k + "\n";
    ADD_FAILURE() << "does not compile:\n" << all;
    return {};
  }
  auto q = parse_bound(question);
  EXPECT_TRUE(q.ok()) << question;
  if (!q) return {};
  return analyse_bound(*c->program, q.value(), options());
}

// A phase `p` holding `body`, run once by the mission.
std::string with_phase(const std::string& body) {
  return body + R"(
mission m {
  place begin = 1, done;
  exit closed;
  transition go  { wait { begin } action { PHASE(p, done) } }
  transition end { wait { done }  signal { closed } }
}
)";
}

TEST(Timing, ASequenceAddsItsCallsTimes) {
  const BoundAnswer a = bound(with_phase(R"(
net p {
  place start = 1, a, b, c;
  exit out;
  transition t1 { wait { start } action { TACTIC(EXEC, set_speed(1), a) } }
  transition t2 { wait { a }     action { TACTIC(EXEC, sleep(2), b) } }
  transition t3 { wait { b }     action { TACTIC(EXEC, surface, c) } }
  transition t4 { wait { c }     signal { out } }
})"),
                              "start p -> exec surface");
  ASSERT_EQ(BoundAnswer::Verdict::Bounded, a.verdict) << a.message;
  EXPECT_NEAR(2.2, a.worst_s, 1e-9);  // 0.1 + (2 + 0.1)
  EXPECT_NEAR(2.0, a.best_s, 1e-9);   // 0 + 2
  ASSERT_FALSE(a.path.empty());
  EXPECT_EQ("fires t3: EXEC surface", a.path.back().what);
  EXPECT_NEAR(2.2, *a.path.back().t_s, 1e-9);
}

TEST(Timing, AChoiceTakesItsLongerBranchAtWorstAndItsShorterAtBest) {
  const BoundAnswer a = bound(with_phase(R"(
net p {
  place start = 1, yes, no, slow, quick, up;
  exit out;
  transition ask   { wait { start } action { TACTIC(ASK, depth_reached, yes, no) } }
  transition short { wait { yes }   action { TACTIC(EXEC, sleep(1), quick) } }
  transition long  { wait { no }    action { TACTIC(EXEC, sleep(3), slow) } }
  transition up1   { wait { quick } action { TACTIC(EXEC, surface, up) } }
  transition up2   { wait { slow }  action { TACTIC(EXEC, surface, up) } }
  transition end   { wait { up }    signal { out } }
})"),
                              "start p -> exec surface");
  ASSERT_EQ(BoundAnswer::Verdict::Bounded, a.verdict) << a.message;
  EXPECT_NEAR(3.2, a.worst_s, 1e-9);
  EXPECT_NEAR(1.0, a.best_s, 1e-9);
}

TEST(Timing, TwoCallsAtOnceTakeTheLongerNotTheSum) {
  const BoundAnswer a = bound(with_phase(R"(
net p {
  place start = 1, a, b, up;
  exit out;
  transition both { wait { start } action { TACTIC(EXEC, sleep(2), a), TACTIC(EXEC, sleep(3), b) } }
  transition join { wait { a, b }  action { TACTIC(EXEC, surface, up) } }
  transition end  { wait { up }    signal { out } }
})"),
                              "start p -> exec surface");
  ASSERT_EQ(BoundAnswer::Verdict::Bounded, a.verdict) << a.message;
  EXPECT_NEAR(3.1, a.worst_s, 1e-9);
  EXPECT_NEAR(3.0, a.best_s, 1e-9);
}

// A loop that asks the fault once a second: the fault just after an answer
// waits one sleep (1 to 1.1 s) and one ask (0 to 0.1 s).
constexpr const char* kPolling = R"(
mission m {
  place begin = 1, due, ok, bad, up;
  exit closed;
  transition wait_a_second { wait { begin } action { TACTIC(EXEC, sleep(1), due) } }
  transition check { wait { due } action { TACTIC(ASK, system_problem, bad, ok) } }
  transition again { wait { ok }  signal { begin } }
  transition rise  { wait { bad } action { TACTIC(EXEC, surface, up) } }
  transition end   { wait { up }  signal { closed } }
}
)";

TEST(Timing, APollingLoopAnswersAFaultWithinOneRound) {
  const BoundAnswer a = bound(kPolling, "fault system_problem -> exec surface");
  ASSERT_EQ(BoundAnswer::Verdict::Bounded, a.verdict) << a.message;
  EXPECT_NEAR(1.2, a.worst_s, 1e-9);
  EXPECT_NEAR(0.0, a.best_s, 1e-9);
  EXPECT_FALSE(a.ends_without);
  auto event = std::find_if(a.path.begin(), a.path.end(), [](const BoundStep& s) { return s.t_s.has_value(); });
  ASSERT_NE(a.path.end(), event);
  EXPECT_EQ("the fault starts: every ask system_problem answers 1 from now on", event->what);
}

TEST(Timing, APollingLoopWithoutTheFaultsAskIsUnbounded) {
  const BoundAnswer a = bound(R"(
mission m {
  place begin = 1, due, there, not_yet, up;
  exit closed;
  transition wait_a_second { wait { begin }   action { TACTIC(EXEC, sleep(1), due) } }
  transition check  { wait { due }     action { TACTIC(ASK, depth_reached, there, not_yet) } }
  transition again  { wait { not_yet } signal { begin } }
  transition rise   { wait { there }   action { TACTIC(EXEC, surface, up) } }
  transition end    { wait { up }      signal { closed } }
  transition never  { wait { up, due } action { TACTIC(ASK, system_problem, up, up) } }
}
)",
                              "fault system_problem -> exec surface");
  ASSERT_EQ(BoundAnswer::Verdict::Unbounded, a.verdict) << a.message;
  ASSERT_FALSE(a.cycle.empty());
  bool asks_depth = false, sleeps = false;
  for (const auto& s : a.cycle) {
    asks_depth |= s.what == "ASK depth_reached answers 0";
    sleeps |= s.what == "fires wait_a_second: EXEC sleep(1)";
  }
  EXPECT_TRUE(asks_depth && sleeps) << a.cycle.size();
}

TEST(Timing, AGuardBoundsTheReactionDuringALongCall) {
  const BoundAnswer a = bound(R"(
mission m {
  place begin = 1, held, up;
  exit closed, aborted;
  guard leak every 1 {
    when   { system_problem }
    action { TACTIC(EXEC, surface, up) }
  }
  transition hold  { wait { begin } action { TACTIC(EXEC, sleep(60), held) } }
  transition done  { wait { held }  signal { closed } }
  transition close { wait { up }    signal { aborted } }
}
)",
                              "fault system_problem -> exec surface");
  ASSERT_EQ(BoundAnswer::Verdict::Bounded, a.verdict) << a.message;
  EXPECT_NEAR(1.2, a.worst_s, 1e-9);
  EXPECT_NEAR(0.0, a.best_s, 1e-9);
  // The same hold without the guard reacts only once the hold is over.
  const BoundAnswer without = bound(R"(
mission m {
  place begin = 1, held, up;
  exit closed, aborted;
  transition hold  { wait { begin } action { TACTIC(EXEC, sleep(60), held) } }
  transition check { wait { held }  action { TACTIC(ASK, system_problem, up, held) } }
  transition close { wait { up }    action { TACTIC(EXEC, surface, up) } }
}
)",
                                    "fault system_problem -> exec surface");
  ASSERT_EQ(BoundAnswer::Verdict::Bounded, without.verdict) << without.message;
  EXPECT_NEAR(60.2, without.worst_s, 1e-9);
}

TEST(Timing, ANestedPhaseRunsInsideItsCaller) {
  const BoundAnswer a = bound(with_phase(R"(
net inner(s) {
  place start = 1, slept, up;
  exit out;
  transition nap  { wait { start } action { TACTIC(EXEC, sleep(s), slept) } }
  transition rise { wait { slept } action { TACTIC(EXEC, surface, up) } }
  transition end  { wait { up }    signal { out } }
}
net p {
  place start = 1, a, b;
  exit out;
  transition first { wait { start } action { TACTIC(EXEC, sleep(1), a) } }
  transition call  { wait { a }     action { PHASE(inner(4), b) } }
  transition end   { wait { b }     signal { out } }
})"),
                              "start p -> exec surface");
  ASSERT_EQ(BoundAnswer::Verdict::Bounded, a.verdict) << a.message;
  EXPECT_NEAR(5.2, a.worst_s, 1e-9);  // sleep(1) + sleep(4), each up to 0.1 s late
  EXPECT_NEAR(5.0, a.best_s, 1e-9);
  bool inner_path = false;
  for (const auto& s : a.path) inner_path |= s.net == "m/p#1/inner#1";
  EXPECT_TRUE(inner_path);
}

TEST(Timing, ToAnExitAndToTheSurfaceWithItsAscent) {
  auto c = testing::compile_text(kPolling);
  ASSERT_TRUE(c->program);
  BoundOptions o = options();
  o.ascent_s = 20.0;
  const BoundAnswer to_exit = analyse_bound(*c->program, parse_bound("fault system_problem -> exit closed").value(), o);
  ASSERT_EQ(BoundAnswer::Verdict::Bounded, to_exit.verdict) << to_exit.message;
  EXPECT_NEAR(1.3, to_exit.worst_s, 1e-9);  // the surface's own answer too
  const BoundAnswer surface = analyse_bound(*c->program, parse_bound("fault system_problem -> surface").value(), o);
  ASSERT_EQ(BoundAnswer::Verdict::Bounded, surface.verdict);
  EXPECT_NEAR(21.2, surface.worst_s, 1e-9);
}

TEST(Timing, WhatTheMissionLacksIsSaid) {
  auto c = testing::compile_text(kPolling);
  ASSERT_TRUE(c->program);
  const auto no_guard = analyse_bound(*c->program, parse_bound("trip leak -> exec surface").value(), options());
  EXPECT_EQ(BoundAnswer::Verdict::Unsupported, no_guard.verdict);
  EXPECT_EQ("no guard named leak in the mission or its phases", no_guard.message);
  const auto no_ask = analyse_bound(*c->program, parse_bound("fault altitude_low -> exec surface").value(), options());
  EXPECT_EQ("no net asks altitude_low", no_ask.message);
  const auto no_exit = analyse_bound(*c->program, parse_bound("fault system_problem -> exit gone").value(), options());
  EXPECT_EQ("the mission has no exit named gone", no_exit.message);
}

TEST(Timing, QuestionsParseAndTheirErrorsSayTheColumn) {
  auto q = parse_bound("  fault not gps_available ->  ood shutdown_network within 12.5 s");
  ASSERT_TRUE(q.ok()) << q.error().message;
  EXPECT_EQ(BoundQuery::From::Fault, q.value().from);
  EXPECT_FALSE(q.value().fault_value);
  EXPECT_EQ("gps_available", q.value().from_name);
  EXPECT_EQ(BoundQuery::To::Call, q.value().to);
  EXPECT_EQ("shutdown_network", q.value().to_name);
  ASSERT_TRUE(q.value().within_s.has_value());
  EXPECT_DOUBLE_EQ(12.5, *q.value().within_s);
  EXPECT_EQ(BoundQuery::To::Surface, parse_bound("trip leak -> surface").value().to);
  EXPECT_TRUE(parse_bound("leak -> surface").error().message.starts_with("column 1: expected fault, trip or start"));
  EXPECT_TRUE(parse_bound("trip leak surface").error().message.starts_with("column 11: expected ->"));
  EXPECT_TRUE(parse_bound("trip leak -> exec").error().message.starts_with("column 18: expected a name after exec"));
  EXPECT_TRUE(
      parse_bound("trip leak -> surface within -1").error().message.starts_with("column 29: expected a number"));
  EXPECT_TRUE(parse_bound("trip leak -> surface soon").error().message.starts_with("column 22: unexpected text"));
}

}  // namespace
}  // namespace strata::coral

namespace strata::coral {
namespace {

// `require "...";`: checked where it is written, and proven by the verifier
// as the mission's blocking property "requirement".
TEST(Requirement, ABadOneIsReportedWhereItIsWritten) {
  auto c = testing::compile_text(R"(net p {
  require "start p -> exit out within 3";
  place start = 1;
  exit out;
  transition t { wait { start } signal { out } }
}
mission m {
  require "fault system_problem -> exec surface";
  require "fault system_problem exec surface within 3";
  place begin = 1, done;
  exit closed;
  transition go  { wait { begin } action { PHASE(p, done) } }
  transition end { wait { done }  signal { closed } }
}
)");
  EXPECT_EQ((std::vector<std::string>{"2:11 BadRequirement", "8:11 BadRequirement", "9:11 BadRequirement"}),
            c->kinds());
  std::vector<std::string> messages;
  for (const auto& d : c->sink.diagnostics()) messages.push_back(d.message);
  EXPECT_EQ("a requirement is the mission's: 'p' is a phase net (move it to the mission)", messages.at(0));
  EXPECT_EQ("a requirement says how long at most: end it with `within S` (seconds)", messages.at(1));
  EXPECT_EQ(
      "requirement: column 22: expected ->: write FROM -> TO, FROM one of `fault ASK`, `fault not ASK`, "
      "`trip GUARD`, `start PHASE`, TO one of `exec NAME`, `ask NAME`, `ood NAME`, `call NAME`, `exit NAME`, "
      "`surface`, then optionally `within S`",
      messages.at(2));
}

TEST(Requirement, TheVerifierHoldsTheMissionToIt) {
  const std::string held = R"(mission m {
  require "fault system_problem -> exec surface within WITHIN";
  place begin = 1, due, ok, bad, up;
  exit closed;
  transition wait_a_second { wait { begin } action { TACTIC(EXEC, sleep(1), due) } }
  transition check { wait { due } action { TACTIC(ASK, system_problem, bad, ok) } }
  transition again { wait { ok }  signal { begin } }
  transition rise  { wait { bad } action { TACTIC(EXEC, surface, up) } }
  transition end   { wait { up }  signal { closed } }
}
)";
  auto property_for = [&](const std::string& within, bool timing) {
    std::string text = held;
    text.replace(text.find("WITHIN"), 6, within);
    auto c = testing::compile_text(text);
    EXPECT_TRUE(c->program.has_value());
    VerifyOptions vo;
    vo.sources = &c->sources;
    if (timing) vo.timing = options();
    const VerifyReport r = verify_program(*c->program, vo);
    for (const auto& p : r.nets.back().properties) {
      if (p.key == "requirement") return p;
    }
    ADD_FAILURE() << "no requirement property";
    return Property{};
  };
  const Property ok = property_for("1.5", true);
  EXPECT_EQ(Property::Status::Holds, ok.status) << ok.message;
  EXPECT_EQ("fault system_problem -> exec surface within 1.5: at worst 1.2 s", ok.message);
  EXPECT_EQ(2u, ok.at.line);
  const Property late = property_for("1", true);
  EXPECT_EQ(Property::Status::Fails, late.status);
  EXPECT_TRUE(late.blocking);
  const Property unknown = property_for("1", false);
  EXPECT_EQ(Property::Status::Undecided, unknown.status);
}

}  // namespace
}  // namespace strata::coral

namespace strata::coral {
namespace {

// What a careless or hostile user may ask: a question a megabyte long, bytes
// that are no text, a thousand questions, and a state limit the model
// passes at once. Each gets its answer or its error, never a hang.
TEST(TimingHostile, LongAndBinaryQuestionsAreRefusedAtTheirColumn) {
  const std::string junk(1 << 20, 'x');
  auto long_one = parse_bound("trip " + junk + " -> surface " + junk);
  ASSERT_FALSE(long_one.ok());
  EXPECT_TRUE(long_one.error().message.starts_with("column 1048594: unexpected text"))
      << long_one.error().message.substr(0, 80);
  auto binary = parse_bound(std::string("fault \0\xff -> surface", 19));
  ASSERT_FALSE(binary.ok());
  EXPECT_TRUE(binary.error().message.starts_with("column 7: expected a name after fault")) << binary.error().message;
  EXPECT_FALSE(parse_bound("").ok());
  EXPECT_FALSE(parse_bound("trip a -> surface within 1e999").ok());
}

TEST(TimingHostile, AThousandQuestionsEachGetTheSameAnswer) {
  auto c = testing::compile_text(kPolling);
  ASSERT_TRUE(c->program);
  const BoundQuery q = parse_bound("fault system_problem -> exec surface").value();
  for (int i = 0; i < 1000; ++i) {
    const BoundAnswer a = analyse_bound(*c->program, q, options());
    ASSERT_EQ(BoundAnswer::Verdict::Bounded, a.verdict);
    ASSERT_NEAR(1.2, a.worst_s, 1e-9);
  }
}

TEST(TimingHostile, TheStateLimitStopsTheExplorationWithItsReason) {
  auto c = testing::compile_text(kPolling);
  ASSERT_TRUE(c->program);
  BoundOptions o = options();
  o.max_states = 5;
  const BoundAnswer a = analyse_bound(*c->program, parse_bound("fault system_problem -> exec surface").value(), o);
  EXPECT_EQ(BoundAnswer::Verdict::Unsupported, a.verdict);
  EXPECT_EQ("more than 5 timed states (--max-states)", a.message);
}

}  // namespace
}  // namespace strata::coral

namespace strata::coral {
namespace {

TEST(TimingHostile, AMissionStatesAtMostSixteenRequirements) {
  std::string text = "mission m {\n";
  for (int i = 0; i < 1000; ++i) text += "  require \"fault system_problem -> exec surface within 2\";\n";
  text += "  place a = 1;\n  exit e;\n  transition t { wait { a } signal { e } }\n}\n";
  auto c = testing::compile_text(text);
  EXPECT_EQ(std::vector<std::string>{"18:11 BadRequirement"}, c->kinds());
}

}  // namespace
}  // namespace strata::coral
