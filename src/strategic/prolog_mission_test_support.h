#pragma once
// What the PROLOG mission tests share: a scratch folder of rule files, a
// host that answers from a script, and the fixture that loads rules.
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include <gtest/gtest.h>

#include "core/diagnostic_printer.h"
#include "strategic/prolog_mission.h"

namespace strata::strategic::prolog_mission_testing {

namespace fs = std::filesystem;

// A scratch folder of rule files for one test.
class Rules {
 public:
  Rules() {
    dir_ = fs::temp_directory_path() /
           ("strata_prolog_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~Rules() { fs::remove_all(dir_); }
  const fs::path& dir() const { return dir_; }
  std::string write(const std::string& name, const std::string& text) {
    fs::create_directories((dir_ / name).parent_path());
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }

 private:
  fs::path dir_;
};

// What a load reported, as the tests read it.
struct Reported {
  core::SourceManager sources;
  core::DiagnosticSink sink;

  std::size_t size() const { return sink.diagnostics().size(); }
  bool empty() const { return size() == 0; }
  const core::Diagnostic& operator[](std::size_t i) const { return sink.diagnostics().at(i); }
  // Diagnostic i's first line as `strata check` prints it: "file:line:col: error: text [Kind]".
  std::string headline(std::size_t i) const {
    std::ostringstream out;
    core::print_diagnostic(out, sources, (*this)[i]);
    std::string text = out.str();
    return text.substr(0, text.find('\n'));
  }
  // Every headline, one a line.
  std::string text() const {
    std::string all;
    for (std::size_t i = 0; i < size(); ++i) all += headline(i) + "\n";
    return all;
  }
  std::string file(std::size_t i) const { return sources.path((*this)[i].span.file); }
  core::LineCol place(std::size_t i) const { return sources.line_col((*this)[i].span.file, (*this)[i].span.offset); }
};

// Answers every call with the next scripted answer and records what happened.
class ScriptedHost final : public PrologHost {
 public:
  std::vector<int> answers;
  std::size_t next_answer = 0;
  bool cancel = false;
  std::vector<std::string> events;

  void primitive(const std::string& name, std::vector<tactical::Value> args) override {
    std::string e = "call " + name;
    for (const auto& a : args) e += " " + tactical::to_string(a);
    events.push_back(e);
    if (on_primitive) on_primitive();
  }
  std::function<void()> on_primitive;  // on the engine's thread, inside the query
  std::optional<int> answer() override {
    if (cancel) return std::nullopt;
    return next_answer < answers.size() ? answers[next_answer++] : 1;
  }
  void report(const std::string& name, std::vector<tactical::Value> args) override {
    events.push_back(name + " " + (args.empty() ? "" : tactical::to_string(args[0])));
    if (on_report) on_report();
  }
  std::function<void()> on_report;  // on the engine's thread, inside the query
  void phase_started(const std::string& phase) override { events.push_back("phase " + phase); }
  void phase_ended(const std::string& phase, const std::string& exit) override {
    events.push_back("end " + phase + " " + exit);
  }
  // Guards: each scope's opening and closing is an event; a test trips a
  // scope by setting `trip` (then answers the call the rules wait in).
  std::optional<GuardTripSignal> trip;
  std::uint64_t open_guards(const std::vector<GuardSpec>& guards) override {
    std::string e = fmt::format("guards #{}", ++scopes);
    for (const auto& g : guards) {
      e += fmt::format(" {}/{}", g.name, g.period_s);
      for (const auto& t : g.terms) e += " [" + t.text + "]";
    }
    events.push_back(e);
    return scopes;
  }
  std::optional<std::string> close_guards(std::uint64_t scope) override {
    events.push_back(fmt::format("close #{}", scope));
    if (!trip || trip->scope != scope) return std::nullopt;
    std::string guard = trip->guard;
    trip.reset();
    return guard;
  }
  std::optional<GuardTripSignal> pending_trip() const override { return trip; }
  void call_not_made(const std::string& name) override { events.push_back("not made " + name); }
  std::uint64_t scopes = 0;
};

class PrologMissionTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { ASSERT_TRUE(prolog::initialise().ok()); }

  std::unique_ptr<PrologMission> load_ok(const std::string& path) {
    Reported reported;
    auto m = PrologMission::load(path, tactical::Catalogue::builtin(), reported.sources, reported.sink);
    if (!reported.empty()) ADD_FAILURE() << reported.text();
    if (!m) ADD_FAILURE() << m.error().message;
    return m ? std::move(m.value()) : nullptr;
  }

  // Runs the query to its end, counting yields (bounded).
  static prolog::Query::Status run(PrologMissionQuery& q, int max_yields = 1000) {
    prolog::Query::Status s;
    int yields = 0;
    while ((s = q.next()) == prolog::Query::Status::Yield && ++yields < max_yields) {}
    return s;
  }

  Rules rules_;
};

}  // namespace strata::strategic::prolog_mission_testing
