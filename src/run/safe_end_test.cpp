// The one safe end against a fake vehicle the test answers by hand, for
// each way it goes: the link gone, already at the surface, surfaced after a
// few seconds, the surface refused, never reaching it, a query or the
// shutdown failing, cut short by a second stop request.
#include "run/safe_end.h"

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "strategic/fake_tactics.h"

namespace strata::run {
namespace {

using Answer = tactical::CallResult;

// The vehicle: each call is answered by `policy` (the call's name and the
// how-many-th call of that name it is), in the order the calls were made.
struct FakeVehicle : strategic::testing::FakeTacticsBase {
  std::function<Answer(const std::string& name, int nth)> policy;

  // Answers pending calls until none is left, or `limit` answers.
  void answer_all(int limit = 10'000) {
    std::map<std::string, int> seen;
    while (!pending.empty() && limit-- > 0) {
      const std::size_t i = pending.front();
      auto done = take(i);
      const std::string& name = calls[i].name;
      done(policy(name, ++seen[name]));
    }
  }
};

Answer yes() { return tactical::CallOutcome{true, 0.0}; }
Answer no() { return tactical::CallOutcome{false, 0.0}; }
Answer failed(std::string why) {
  return tactical::CallError{tactical::CallError::Kind::TimedOut, std::nullopt, std::move(why)};
}

struct SafeEndRig {
  FakeVehicle vehicle;
  std::vector<std::string> said;
  SafeEnd safe_end{vehicle, tactical::Catalogue::builtin(), [this](const std::string& s) { said.push_back(s); }};
  int done_calls = 0;

  void run(bool link_gone) {
    safe_end.run(link_gone, [this] { ++done_calls; });
    vehicle.answer_all();
  }
};

TEST(SafeEnd, WithTheLinkGoneOnlyTheShutdownIsTried) {
  SafeEndRig rig;
  rig.vehicle.policy = [](const std::string&, int) { return yes(); };
  EXPECT_EQ("ood shutdown_network", rig.safe_end.plan(/*link_gone=*/true));
  rig.run(/*link_gone=*/true);
  EXPECT_EQ("shutdown_network", rig.vehicle.names());
  EXPECT_EQ(1, rig.done_calls);
  EXPECT_TRUE(rig.safe_end.shutdown_sent());
  EXPECT_FALSE(rig.safe_end.surface_commanded());
}

TEST(SafeEnd, AVehicleAlreadyAtTheSurfaceIsOnlySentDone) {
  SafeEndRig rig;
  rig.vehicle.policy = [](const std::string&, int) { return yes(); };
  rig.run(false);
  EXPECT_EQ("surface_reached shutdown_network", rig.vehicle.names());
  EXPECT_TRUE(rig.safe_end.surfaced());
  EXPECT_FALSE(rig.safe_end.surface_commanded());
  EXPECT_EQ("", rig.safe_end.shutdown_error());
  EXPECT_EQ(1, rig.done_calls);
}

TEST(SafeEnd, AVehicleAtDepthIsSurfacedThenSentDone) {
  SafeEndRig rig;
  // Under water at first; at the surface on the third poll.
  rig.vehicle.policy = [](const std::string& name, int nth) {
    if (name == "surface_reached") return nth >= 3 ? yes() : no();
    return yes();
  };
  rig.run(false);
  EXPECT_EQ("surface_reached surface surface_reached sleep(1) surface_reached shutdown_network", rig.vehicle.names());
  EXPECT_TRUE(rig.safe_end.surface_commanded());
  EXPECT_TRUE(rig.safe_end.surfaced());
  EXPECT_EQ(1, rig.done_calls);
}

TEST(SafeEnd, ASurfaceTheVehicleRefusesIsSaidAndDoneIsStillSent) {
  SafeEndRig rig;
  rig.vehicle.policy = [](const std::string& name, int) { return name == "shutdown_network" ? yes() : no(); };
  rig.run(false);
  EXPECT_EQ("surface_reached surface shutdown_network", rig.vehicle.names());
  EXPECT_TRUE(rig.safe_end.surface_commanded());
  EXPECT_FALSE(rig.safe_end.surfaced());
  ASSERT_FALSE(rig.said.empty());
  EXPECT_EQ("exec surface: the vehicle answered 0", rig.said.front());
  EXPECT_TRUE(rig.safe_end.shutdown_sent());
}

TEST(SafeEnd, AVehicleThatNeverSurfacesIsSentDoneAfterTheLimit) {
  SafeEndRig rig;
  rig.vehicle.policy = [](const std::string& name, int) { return name == "surface_reached" ? no() : yes(); };
  rig.run(false);
  int polls = 0;
  for (const auto& c : rig.vehicle.calls) polls += c.name == "surface_reached" ? 1 : 0;
  EXPECT_EQ(1 + 121, polls);  // the first question, then once a second for 120 s and a last look
  EXPECT_EQ("shutdown_network", rig.vehicle.calls.back().name);
  ASSERT_FALSE(rig.said.empty());
  EXPECT_EQ("the vehicle did not reach the surface in 120 s", rig.said.back());
  EXPECT_FALSE(rig.safe_end.surfaced());
  EXPECT_EQ(1, rig.done_calls);
}

TEST(SafeEnd, AQueryThatFailsGoesStraightToDone) {
  SafeEndRig rig;
  rig.vehicle.policy = [](const std::string& name, int) {
    return name == "surface_reached" ? failed("no reply in 1 s") : yes();
  };
  rig.run(false);
  EXPECT_EQ("surface_reached shutdown_network", rig.vehicle.names());
  EXPECT_FALSE(rig.safe_end.surfaced());
  EXPECT_EQ("ask surface_reached failed: no reply in 1 s", rig.said.front());
}

TEST(SafeEnd, AShutdownThatFailsIsRecordedAndTheProcedureStillEnds) {
  SafeEndRig rig;
  rig.vehicle.policy = [](const std::string& name, int) {
    return name == "shutdown_network" ? failed("the link is closed") : yes();
  };
  rig.run(false);
  EXPECT_TRUE(rig.safe_end.shutdown_sent());
  EXPECT_EQ("the link is closed", rig.safe_end.shutdown_error());
  EXPECT_EQ(1, rig.done_calls);
}

TEST(SafeEnd, ASecondStopRequestEndsItAtOnceAndLaterRepliesAreIgnored) {
  SafeEndRig rig;
  rig.vehicle.policy = [](const std::string&, int) { return no(); };
  rig.safe_end.run(false, [&] { ++rig.done_calls; });
  ASSERT_EQ(1u, rig.vehicle.pending.size());  // ask surface_reached, unanswered
  rig.safe_end.abandon();
  EXPECT_EQ(1, rig.done_calls);
  EXPECT_EQ("the safe end was cut short: the vehicle's last answers are not waited for", rig.said.back());
  rig.vehicle.answer_all();  // the reply comes late: nothing more is sent
  EXPECT_EQ("surface_reached", rig.vehicle.names());
  EXPECT_EQ(1, rig.done_calls);
}

TEST(SafeEnd, ACatalogueWithoutTheShutdownHasNothingToDo) {
  auto catalogue = tactical::Catalogue::parse(
      "[[primitive]]\nname = \"surface\"\nkind = \"exec\"\ntimeout_s = 2\ndoc = \"up\"\n"
      "message = \"exec surface\"\n",
      "test.toml");
  ASSERT_TRUE(catalogue) << catalogue.error().message;
  FakeVehicle vehicle;
  SafeEnd safe_end(vehicle, catalogue.value(), [](const std::string&) {});
  EXPECT_FALSE(safe_end.possible());
}

}  // namespace
}  // namespace strata::run
