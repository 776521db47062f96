// The PROLOG mission driver interrupted from another thread (as the signal
// watcher and the studio's Stop do).
#include "strategic/prolog_mission.h"

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <thread>

#include <gtest/gtest.h>

#include "strategic/prolog_mission_test_support.h"

namespace strata::strategic {
namespace {

namespace fs = std::filesystem;
using prolog_mission_testing::PrologMissionTest;
using prolog_mission_testing::Rules;
using prolog_mission_testing::ScriptedHost;

using Clock = std::chrono::steady_clock;

// Interrupts a host's rules from another thread, as a thread that watches
// for SIGINT would: once the rules report (plus delay, so that a rule that
// sleeps next is inside sleep/1), it calls interrupt_rules() until the rules
// are seen running (bounded).
class Interrupter {
 public:
  Interrupter(ScriptedHost& host, std::chrono::milliseconds delay) {
    host.on_report = [this] {
      std::lock_guard lock(mutex_);
      ready_ = true;
      cv_.notify_one();
    };
    thread_ = std::thread([this, &host, delay] {
      std::unique_lock lock(mutex_);
      if (!cv_.wait_for(lock, std::chrono::seconds(10), [this] { return ready_; })) return;
      lock.unlock();
      std::this_thread::sleep_for(delay);
      for (int attempt = 0; attempt < 1000 && !interrupted_; ++attempt) {
        at_ = Clock::now();
        interrupted_ = interrupt_rules(host);
        if (!interrupted_) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    });
  }
  ~Interrupter() { join(); }
  void join() {
    if (thread_.joinable()) thread_.join();
  }
  bool interrupted() const { return interrupted_; }
  Clock::time_point at() const { return at_; }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  bool ready_ = false;
  bool interrupted_ = false;
  Clock::time_point at_;
  std::thread thread_;
};

double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

TEST_F(PrologMissionTest, InterruptFromAnotherThreadStopsRulesInSleep) {
  auto m =
      load_ok(rules_.write("m.pl", "mission :- exec_start_timer(_), report(ready), sleep(30), exec_surface(_).\n"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 100000);
  ASSERT_EQ(prolog::Query::Status::Yield, q.next());
  Interrupter interrupter(host, std::chrono::milliseconds(50));
  Clock::time_point start = Clock::now();
  EXPECT_EQ(prolog::Query::Status::Exception, q.next());
  double latency_ms = ms_since(interrupter.at());
  interrupter.join();
  ASSERT_TRUE(interrupter.interrupted());
  EXPECT_TRUE(q.interrupted()) << q.exception_text();
  EXPECT_EQ("strata_interrupted", q.exception_text());
  EXPECT_LT(ms_since(start), 10'000.0) << "a guard: sleep(30) was not cut short";
  RecordProperty("interrupt_latency_ms", std::to_string(latency_ms));
  EXPECT_EQ((std::vector<std::string>{"call start_timer", "report ready"}), host.events);
}

TEST_F(PrologMissionTest, InterruptStopsABusyLoopUnderAHugeInferenceLimitAndACatchAll) {
  for (std::string loop : {"repeat, fail", "count(0)", "catch((repeat, fail), _, true), exec_surface(_)",
                           "repeat, catch(count(0), _, true), fail"}) {
    auto m = load_ok(rules_.write("m.pl", "mission :- report(ready), " + loop +
                                              ".\n"
                                              "count(N) :- M is N + 1, count(M).\n"));
    ASSERT_TRUE(m);
    ScriptedHost host;
    PrologMissionQuery q(*m, host, 1'000'000'000'000);
    Interrupter interrupter(host, std::chrono::milliseconds(0));
    Clock::time_point start = Clock::now();
    EXPECT_EQ(prolog::Query::Status::Exception, q.next()) << loop;
    double latency_ms = ms_since(interrupter.at());
    interrupter.join();
    ASSERT_TRUE(interrupter.interrupted()) << loop;
    EXPECT_TRUE(q.interrupted()) << loop << ": " << q.exception_text().substr(0, 200);
    EXPECT_FALSE(q.inference_limit_exceeded()) << loop;
    EXPECT_LT(ms_since(start), 10'000.0) << loop << ": a guard";
    RecordProperty("interrupt_latency_ms", std::to_string(latency_ms));
    EXPECT_EQ(std::vector<std::string>{"report ready"}, host.events) << loop << ": nothing ran after it";
  }
}

TEST_F(PrologMissionTest, InterruptWhileTheRulesWaitForTheVehicleDoesNothing) {
  auto m = load_ok(rules_.write("m.pl",
                                "mission :- exec_sleep(1, _), burn, exec_surface(_).\n"
                                "burn :- between(1, 20000, _), fail ; true.\n"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  PrologMissionQuery q(*m, host, 100000);
  ASSERT_EQ(prolog::Query::Status::Yield, q.next());
  EXPECT_FALSE(interrupt_rules(host)) << "the rules wait for the vehicle: nothing runs to stop";
  ScriptedHost other;
  EXPECT_FALSE(interrupt_rules(other)) << "not the host whose rules run";
  EXPECT_EQ(prolog::Query::Status::Yield, q.next()) << q.exception_text();
  auto s = q.next();
  EXPECT_TRUE(s == prolog::Query::Status::True || s == prolog::Query::Status::Last) << q.exception_text();
  EXPECT_FALSE(q.interrupted());
  EXPECT_EQ((std::vector<std::string>{"call sleep 1", "call surface"}), host.events);
}

TEST_F(PrologMissionTest, AStaleInterruptCannotStopTheRulesLaterOrTheNextQuery) {
  // Raised as the rules yield (from inside the primitive call, on the
  // engine's thread): the query returns before it reaches a call port, so
  // the raise is still pending in SWI when next() returns.
  auto m = load_ok(rules_.write("m.pl",
                                "mission :- exec_sleep(1, _), burn, exec_surface(_).\n"
                                "burn :- between(1, 20000, _), fail ; true.\n"));
  ASSERT_TRUE(m);
  ScriptedHost host;
  bool raised = false;
  host.on_primitive = [&] {
    if (!raised) raised = interrupt_rules(host);
  };
  PrologMissionQuery q(*m, host, 100000);
  ASSERT_EQ(prolog::Query::Status::Yield, q.next()) << q.exception_text();
  ASSERT_TRUE(raised) << "the rules were running: the raise was made";
  EXPECT_FALSE(q.interrupted());
  // Resumed, the rules run on: the raise belonged to the scope that closed.
  EXPECT_EQ(prolog::Query::Status::Yield, q.next()) << q.exception_text();
  auto s = q.next();
  EXPECT_TRUE(s == prolog::Query::Status::True || s == prolog::Query::Status::Last) << q.exception_text();
  EXPECT_FALSE(q.interrupted());
  q.close();

  // The same as the last thing a query does: the next query is not hit.
  auto again = load_ok(rules_.write("again.pl",
                                    "mission :- exec_surface(_), burn, exec_surface(_).\n"
                                    "burn :- between(1, 20000, _), fail ; true.\n"));
  ASSERT_TRUE(again);
  ScriptedHost last;
  bool raised_last = false;
  last.on_primitive = [&] {
    if (!raised_last) raised_last = interrupt_rules(last);
  };
  {
    PrologMissionQuery first(*again, last, 100000);
    ASSERT_EQ(prolog::Query::Status::Yield, first.next());
    ASSERT_TRUE(raised_last);
  }  // closed while the raise is pending
  auto third = load_ok(rules_.write("third.pl",
                                    "mission :- burn, exec_surface(_).\n"
                                    "burn :- between(1, 20000, _), fail ; true.\n"));
  ASSERT_TRUE(third);
  ScriptedHost fresh;
  PrologMissionQuery next(*third, fresh, 100000);
  EXPECT_EQ(prolog::Query::Status::Yield, next.next()) << next.exception_text();
  EXPECT_EQ(prolog::Query::Status::Last, next.next()) << next.exception_text();
  EXPECT_FALSE(next.interrupted());
  EXPECT_TRUE(prolog::call_once("between(1, 1000, _), fail ; true").value()) << "Prolog runs on";
}

}  // namespace
}  // namespace strata::strategic
