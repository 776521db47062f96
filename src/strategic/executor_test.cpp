#include "strategic/executor.h"

#include <string>

#include <gtest/gtest.h>

namespace strata::strategic {
namespace {

// Records what it hears, in order, as one string.
struct EventRecorder : Observer {
  std::string* said;
  explicit EventRecorder(std::string* s) : said(s) {}
  void phase_ended(const PhaseEnd& e) override { *said += "phase_ended:" + std::string(e.name) + " "; }
  void mission_ended(const MissionResult& r) override { *said += "mission_ended:" + r.reason + " "; }
};

// The least executor: ends its one phase in wind_down().
class OnePhase final : public ExecutorBase {
 public:
  explicit OnePhase(std::string* said) : said_(said) {}
  void start(std::function<void(const MissionResult&)> on_end) override {
    if (!begin(std::move(on_end))) *said_ += "refused ";
  }
  void cancel(std::string reason) override { finish({Outcome::Failed, "", std::move(reason), std::nullopt, 0.0}); }

 private:
  void wind_down(const MissionResult&) override {
    *said_ += "wind_down ";
    observers_.phase_ended({0, "mission", "", 0, true, 0.0});
  }
  std::string* said_;
};

TEST(ExecutorBase, FinishWindsDownThenTellsObserversThenCallsOnEndOnce) {
  std::string said;
  EventRecorder a(&said), b(&said);
  OnePhase executor(&said);
  executor.add_observer(a);
  executor.add_observer(b);
  int ends = 0;
  executor.start([&](const MissionResult& r) {
    ++ends;
    said += "on_end:" + r.reason + " ";
    EXPECT_FALSE(executor.running());
  });
  EXPECT_TRUE(executor.running());
  executor.cancel("stop");
  executor.cancel("again");  // ended: nothing more
  EXPECT_EQ(1, ends);
  EXPECT_EQ("wind_down phase_ended:mission phase_ended:mission mission_ended:stop mission_ended:stop on_end:stop ",
            said);
}

TEST(ExecutorBase, AnExecutorRunsOneMission) {
  std::string said;
  OnePhase executor(&said);
  executor.start(nullptr);
  executor.cancel("stop");
  executor.start(nullptr);
  EXPECT_FALSE(executor.running());
  EXPECT_EQ("wind_down refused ", said);
}

}  // namespace
}  // namespace strata::strategic
