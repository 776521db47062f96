// Questions on mission nets (verify_question.h) against the verifier's own
// exploration of the same analysis nets.
#include "coral/verify_question.h"

#include <gtest/gtest.h>

#include "coral/test_support.h"
#include "coral/verifier.h"

namespace strata::coral {
namespace {

using testing::compile_text;

// A phase that can only end at `done` (its `failed` exit is never marked
// by a reachable firing), called by a mission.
constexpr const char* kMissionWithPhase =
    "net p { place s = 1, a, b, never; exit done, failed;\n"
    "  transition ask { wait { s } action { TACTIC(ASK, depth_reached, a, b) } }\n"
    "  transition yes { wait { a } signal { done } }\n"
    "  transition no { wait { b } signal { a } }\n"
    "  transition fail { wait { never } signal { failed } } }\n"
    "mission m { place begin = 1, ok, bad, stuck;\n"
    "  transition go { wait { begin } action { PHASE(p, ok, bad) } }\n"
    "  transition cleanup { wait { bad } signal { stuck } } }\n";

petri::QuestionResult ask(const Program& program, std::string_view net, std::string_view text) {
  auto an = question_analysis_net(program, net, {});
  EXPECT_TRUE(an.ok()) << (an ? "" : an.error().message);
  if (!an) return {};
  auto q = petri::parse_question(text, petri::net_place_resolver(an.value().net));
  EXPECT_TRUE(q.ok()) << (q ? "" : q.error().message);
  if (!q) return {};
  petri::QuestionOptions o;
  o.terminal_places = an.value().exits;
  auto r = petri::answer_question(an.value().net, q.value(), o);
  if (r.has_witness) {
    const petri::ReplayResult rep = petri::replay(an.value().net, r.witness);
    EXPECT_TRUE(rep.complete) << rep.error;
    EXPECT_EQ(r.witness_marking, rep.marking);
  }
  return r;
}

TEST(MissionQuestion, PhaseOutcomesAreNarrowedToTheReachableExits) {
  auto c = compile_text(kMissionWithPhase);
  ASSERT_TRUE(c->program);
  EXPECT_EQ(petri::Answer::Yes, ask(*c->program, "", "EF ok >= 1").answer);
  // `failed` is never reached, so the mission never gets `bad`.
  EXPECT_EQ(petri::Answer::No, ask(*c->program, "", "EF bad >= 1").answer);
  EXPECT_EQ(petri::Answer::Yes, ask(*c->program, "", "AG stuck == 0").answer);
  EXPECT_EQ(petri::Answer::Yes, ask(*c->program, "p", "EF done >= 1").answer);
  EXPECT_EQ(petri::Answer::No, ask(*c->program, "p", "EF failed >= 1").answer);
  // In flight: the ASK's place, named TRANSITION.PRIMITIVE.
  EXPECT_EQ(petri::Answer::Yes, ask(*c->program, "p", "EF ask.depth_reached == 1").answer);
}

TEST(MissionQuestion, DeadlockAgreesWithTheVerifier) {
  auto c = compile_text(kMissionWithPhase);
  ASSERT_TRUE(c->program);
  const VerifyReport report = verify_program(*c->program);
  for (const NetVerification& n : report.nets) {
    bool deadlock_free = false;
    for (const Property& p : n.properties) {
      if (p.key == "no_deadlock") deadlock_free = p.status == Property::Status::Holds;
    }
    const petri::QuestionResult r = ask(*c->program, n.name, "deadlock");
    if (n.name == "m") {
      // A mission net without exits ends when nothing is enabled and nothing
      // is in flight: the verifier does not call that a deadlock; the
      // question finds it (the marking where the run ends).
      EXPECT_TRUE(deadlock_free);
      EXPECT_EQ(petri::Answer::Yes, r.answer);
      continue;
    }
    EXPECT_EQ(deadlock_free ? petri::Answer::No : petri::Answer::Yes, r.answer) << n.name;
  }
}

TEST(MissionQuestion, UnknownNetNamesTheNets) {
  auto c = compile_text(kMissionWithPhase);
  ASSERT_TRUE(c->program);
  auto an = question_analysis_net(*c->program, "q", {});
  ASSERT_FALSE(an.ok());
  EXPECT_EQ("no net 'q' (there are: p, m)", an.error().message);
}

}  // namespace
}  // namespace strata::coral
