#pragma once
// Shared by the PROLOG executor tests (prolog_executor_test.cpp and
// prolog_interrupt_test.cpp): a scripted Tactical level, an observer that
// records, and the fixture that loads rules from text.
#include "strategic/prolog_executor.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <sstream>
#include <thread>

#include <asio.hpp>

#include <fmt/format.h>

#include <gtest/gtest.h>

#include "core/diagnostic_printer.h"
#include "prolog/engine.h"
#include "strategic/fake_tactics.h"
#include "tactical/catalogue.h"

namespace strata::strategic::prolog_testing {

namespace fs = std::filesystem;
using Strings = std::vector<std::string>;

// Answers the call the rules wait for: the newest unanswered one that is
// not a REPORT.
struct FakeTactics final : testing::FakeTacticsBase {
  void call(std::string_view name, std::vector<tactical::Value> args, tactical::CallHandler done) override {
    FakeTacticsBase::call(name, std::move(args), std::move(done));
    if (on_call) on_call(calls.back());
  }
  // Told of each call as it is made (on the loop's thread, from inside the rules).
  std::function<void(const Call&)> on_call;
  std::size_t waited_for() const {
    auto it = std::find_if(pending.rbegin(), pending.rend(), [&](std::size_t i) { return calls[i].name != "report"; });
    return it == pending.rend() ? calls.size() : *it;
  }
  void answer(bool value) {
    std::size_t i = waited_for();
    ASSERT_LT(i, calls.size()) << "no call to answer";
    time_s += 0.1;
    take(i)(tactical::CallOutcome{value, time_s});
  }
  void fail_call(tactical::CallError error) {
    std::size_t i = waited_for();
    ASSERT_LT(i, calls.size()) << "no call to fail";
    take(i)(std::move(error));
  }
  // Delivers the (ignored) replies of every REPORT sent so far.
  void answer_reports() {
    for (std::size_t i : std::deque<std::size_t>(pending)) {
      if (calls[i].name == "report") take(i)(tactical::CallOutcome{true, time_s});
    }
  }
};

// Records what observers are told, in one sequence of short strings.
struct Recorder final : Observer {
  void phase_started(const PhaseStart& e) override {
    events.push_back(fmt::format("start {}#{} parent {} depth {}", e.name, e.instance, e.parent, e.depth));
    EXPECT_EQ("", e.caller);
    EXPECT_EQ(nullptr, e.state);
  }
  void phase_ended(const PhaseEnd& e) override {
    events.push_back(e.cancelled ? fmt::format("end {}#{} cancelled", e.name, e.instance)
                                 : fmt::format("end {}#{} '{}' {}", e.name, e.instance, e.exit, e.exit_index));
  }
  void action_started(const ActionStart& e) override {
    events.push_back(fmt::format("action {} {} {} in {}", e.id, e.kind_name(), e.primitive, e.instance));
  }
  void action_finished(const ActionFinish& e) override {
    events.push_back(fmt::format("finish {} {}={} in {}#{}", e.id, e.primitive, e.value ? 1 : 0, e.net, e.instance));
  }
  void notice(const Notice& e) override { notices.push_back(e.text); }
  void mission_ended(const MissionResult& r) override {
    events.push_back(fmt::format("mission_ended {}", to_string(r.outcome)));
    ++ended;
  }

  Strings events;
  Strings notices;
  int ended = 0;
};

// One executor run on one mission, its fake Tactical level and its recorder.
struct Session {
  explicit Session(PrologMission& mission, PrologOptions options = {})
      : executor(std::make_unique<PrologExecutor>(mission, tactics, tactical::Catalogue::builtin(), options)) {
    executor->add_observer(recorder);
  }
  void start() {
    executor->start([this](const MissionResult& r) {
      recorder.events.push_back("on_end");
      ++on_end_calls;
      result = r;
    });
  }
  bool ended_with(Outcome outcome) const { return result && result->outcome == outcome; }
  std::string why() const { return result ? result->reason : "still running"; }
  // The last n events.
  Strings last(std::size_t n) const {
    return Strings(recorder.events.end() - static_cast<std::ptrdiff_t>(std::min(n, recorder.events.size())),
                   recorder.events.end());
  }

  FakeTactics tactics;
  Recorder recorder;
  std::unique_ptr<PrologExecutor> executor;
  std::optional<MissionResult> result;
  int on_end_calls = 0;
};

class PrologExecutorTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { ASSERT_TRUE(prolog::initialise().ok()); }

  PrologExecutorTest() {
    dir_ = fs::temp_directory_path() / fmt::format("strata_prolog_executor_{}_{}",
                                                   ::testing::UnitTest::GetInstance()->random_seed(),
                                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~PrologExecutorTest() override { fs::remove_all(dir_); }

  static std::string read_file(const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  static std::unique_ptr<PrologMission> load(const std::string& path) {
    core::SourceManager sources;
    core::DiagnosticSink sink;
    auto m = PrologMission::load(path, tactical::Catalogue::builtin(), sources, sink);
    if (!sink.diagnostics().empty()) {
      std::ostringstream text;
      core::print_diagnostics(text, sources, sink.diagnostics());
      ADD_FAILURE() << text.str();
    }
    if (!m) ADD_FAILURE() << m.error().message;
    return m ? std::move(m.value()) : nullptr;
  }
  std::unique_ptr<PrologMission> rules(const std::string& name, const std::string& text) {
    return load(write(name + ".pl", text));
  }
  // Loads rules (kept until the test ends), starts them and answers their calls in turn.
  std::unique_ptr<Session> run(const std::string& name, const std::string& text, const std::vector<bool>& answers,
                               PrologOptions options = {}) {
    missions_.push_back(rules(name, text));
    if (!missions_.back()) return nullptr;
    auto session = std::make_unique<Session>(*missions_.back(), options);
    session->start();
    for (bool answer : answers) session->tactics.answer(answer);
    return session;
  }

  fs::path dir_;
  std::vector<std::unique_ptr<PrologMission>> missions_;
};

}  // namespace strata::strategic::prolog_testing
