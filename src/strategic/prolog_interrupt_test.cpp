// Executor::interrupt on the PROLOG executor, from another thread: rules in
// sleep/1, busy loops, catch-alls; a stale interrupt never reaches the next run.
#include "strategic/prolog_executor_test_support.h"

namespace strata::strategic::prolog_testing {
namespace {

using Clock = std::chrono::steady_clock;

// strata run's shape: the executor on an io_context driven by this thread;
// another thread (the one that would sigwait() for SIGINT) interrupts it
// once the rules report `ready` (plus delay, so that a rule that sleeps next
// is inside sleep/1), then posts cancel() to the loop.
struct InterruptedRun {
  static constexpr const char* kReason = "interrupted by SIGINT";

  InterruptedRun(Session& s, std::chrono::milliseconds delay) : session(s) {
    session.tactics.on_call = [this](const FakeTactics::Call& c) {
      if (c.name != "report") return;
      std::lock_guard lock(mutex);
      ready = true;
      cv.notify_one();
    };
    watcher = std::thread([this, delay] {
      {
        std::unique_lock lock(mutex);
        if (!cv.wait_for(lock, std::chrono::seconds(10), [this] { return ready; })) return;
      }
      std::this_thread::sleep_for(delay);
      interrupted_at = Clock::now();
      this->session.executor->interrupt(kReason);
      asio::post(io, [this] { this->session.executor->cancel(kReason); });
    });
  }
  ~InterruptedRun() {
    if (watcher.joinable()) watcher.join();
  }

  // Runs the loop until the mission ends (20 s at most: a guard, not a
  // measure); returns the time from the interrupt to the end, in ms.
  double run() {
    auto work = asio::make_work_guard(io);
    asio::post(io, [this] { session.start(); });
    Clock::time_point deadline = Clock::now() + std::chrono::seconds(20);
    while (!session.result && Clock::now() < deadline) io.run_one_for(std::chrono::milliseconds(100));
    Clock::time_point ended = Clock::now();
    watcher.join();
    io.poll();  // the posted cancel: it finds the mission ended
    return std::chrono::duration<double, std::milli>(ended - interrupted_at).count();
  }

  Session& session;
  asio::io_context io;
  std::mutex mutex;
  std::condition_variable cv;
  bool ready = false;
  Clock::time_point interrupted_at;
  std::thread watcher;
};

TEST_F(PrologExecutorTest, InterruptEndsAMissionWhoseRulesAreInSleep) {
  auto m = rules("sleeping", R"(
mission :- exec_start_timer(_), execute_phase(wait).
execute_phase(wait) :- report(ready), sleep(30), exec_surface(_).
)");
  ASSERT_TRUE(m);
  Session s(*m);
  s.tactics.time_s = 12.5;
  InterruptedRun run(s, std::chrono::milliseconds(50));
  // The timer's reply is given on the loop as a vehicle's would be.
  s.tactics.on_call = [&, report = s.tactics.on_call](const FakeTactics::Call& c) {
    if (c.name == "start_timer") {
      asio::post(run.io, [&] { s.tactics.answer(true); });
    } else {
      report(c);
    }
  };
  Clock::time_point start = Clock::now();
  double latency_ms = run.run();
  ASSERT_TRUE(s.ended_with(Outcome::Failed)) << s.why();
  EXPECT_EQ("interrupted by SIGINT", s.result->reason);
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 15.0) << "a guard: sleep(30) ran on";
  RecordProperty("interrupt_to_end_ms", std::to_string(latency_ms));
  EXPECT_EQ("start_timer report(ready)", s.tactics.names()) << "the rules did not go on";
  EXPECT_EQ((Strings{"end wait#1 cancelled", "end sleeping#0 cancelled", "mission_ended failed", "on_end"}), s.last(4));
  EXPECT_EQ(1, s.on_end_calls);
  EXPECT_FALSE(s.executor->running());
}

TEST_F(PrologExecutorTest, InterruptEndsABusyLoopUnderAHugeInferenceLimitAlsoInsideACatchAll) {
  for (std::string loop : {"repeat, fail", "count(0)", "catch((repeat, fail), _, true), exec_surface(_)",
                           "repeat, catch(count(0), _, true), fail"}) {
    auto m = rules("busy", "mission :- report(ready), " + loop + ".\ncount(N) :- M is N + 1, count(M).\n");
    ASSERT_TRUE(m);
    Session s(*m, PrologOptions{1'000'000'000'000});
    InterruptedRun run(s, std::chrono::milliseconds(0));
    double latency_ms = run.run();
    ASSERT_TRUE(s.ended_with(Outcome::Failed)) << loop << ": " << s.why();
    EXPECT_EQ("interrupted by SIGINT", s.result->reason) << loop;
    RecordProperty("interrupt_to_end_ms", std::to_string(latency_ms));
    EXPECT_EQ("report(ready)", s.tactics.names()) << loop << ": nothing ran after it";
    EXPECT_EQ(1, s.on_end_calls) << loop;
  }
}

TEST_F(PrologExecutorTest, InterruptWhileWaitingForTheVehicleLeavesTheEndToCancelAndTheNextRunRuns) {
  const std::string text =
      "mission :- exec_sleep(1, _), burn, exec_surface(_).\n"
      "burn :- between(1, 20000, _), fail ; true.\n";
  auto m = rules("waiting", text);
  ASSERT_TRUE(m);
  Session s(*m);
  s.start();
  ASSERT_EQ("sleep(1)", s.tactics.names());
  std::thread([&] { s.executor->interrupt("interrupted by SIGINT"); }).join();
  EXPECT_FALSE(s.result) << "nothing ran to stop: the posted cancel ends it";
  EXPECT_TRUE(s.executor->running());
  s.executor->cancel("interrupted by SIGINT");
  ASSERT_TRUE(s.ended_with(Outcome::Failed));
  EXPECT_EQ("interrupted by SIGINT", s.result->reason);
  s.tactics.answer(true);  // late: a notice, the rules do not run
  EXPECT_EQ(1u, s.recorder.notices.size());
  EXPECT_EQ("sleep(1)", s.tactics.names());

  // The reply may come before the posted cancel: the rules do not run again.
  auto m2 = rules("reply_first", text);
  ASSERT_TRUE(m2);
  Session r(*m2);
  r.start();
  std::thread([&] { r.executor->interrupt("stopped from the studio"); }).join();
  r.tactics.answer(true);
  ASSERT_TRUE(r.ended_with(Outcome::Failed)) << r.why();
  EXPECT_EQ("stopped from the studio", r.result->reason);
  EXPECT_EQ("sleep(1)", r.tactics.names());
  r.executor->cancel("stopped from the studio");
  EXPECT_EQ(1, r.on_end_calls);

  // An interrupt before start() or after the end changes nothing.
  auto m3 = rules("next_run", text);
  ASSERT_TRUE(m3);
  Session n(*m3);
  n.executor->interrupt("too early");
  n.start();
  n.tactics.answer(true);
  n.tactics.answer(true);
  ASSERT_TRUE(n.ended_with(Outcome::Completed)) << n.why();
  n.executor->interrupt("too late");
  EXPECT_EQ("sleep(1) surface", n.tactics.names());
}

TEST_F(PrologExecutorTest, AnInterruptFromInsideTheRulesEndsTheMissionAndDoesNotReachTheNextRun) {
  // Made on the loop's thread while the rules run (a REPORT is sent from
  // inside them): they stop at their next call.
  const std::string text =
      "mission :- exec_sleep(1, _), report(ready), burn, exec_surface(_).\n"
      "burn :- between(1, 20000, _), fail ; true.\n";
  auto m = rules("from_inside", text);
  ASSERT_TRUE(m);
  Session s(*m);
  s.tactics.on_call = [&](const FakeTactics::Call& c) {
    if (c.name == "report") s.executor->interrupt("interrupted by SIGTERM");
  };
  s.start();
  s.tactics.answer(true);
  ASSERT_TRUE(s.ended_with(Outcome::Failed)) << s.why();
  EXPECT_EQ("interrupted by SIGTERM", s.result->reason);
  EXPECT_EQ("sleep(1) report(ready)", s.tactics.names());

  auto next = rules("after_it", text);
  ASSERT_TRUE(next);
  Session n(*next);
  n.start();
  n.tactics.answer(true);
  n.tactics.answer(true);
  ASSERT_TRUE(n.ended_with(Outcome::Completed)) << n.why();
  EXPECT_EQ("sleep(1) report(ready) surface", n.tactics.names());
}

}  // namespace
}  // namespace strata::strategic::prolog_testing
