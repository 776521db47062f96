// Language tests written in CORAL:
//  - tests/coral/ok/NAME.coral must compile with no diagnostic, and its
//    `strata dump` must equal NAME.dump (STRATA_UPDATE_GOLDEN=1 rewrites it);
//  - tests/coral/fail_NAME.coral must give exactly the diagnostics its
//    annotations list, one per line: `// error: LINE:COL [Kind]` or
//    `// warning: LINE:COL [Kind]`; a diagnostic in an imported file is
//    annotated with that file's path relative to this one:
//    `// error: fail_lib/x.coral:3:1 [ImportCycle]`. A file with a line
//    `// vehicle: imc://HOST:PORT` is checked for that vehicle, as
//    `strata check --vehicle imc://HOST:PORT` checks it.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "coral/compiler.h"
#include "core/diagnostic_printer.h"
#include "strategic/coral_catalogue.h"
#include "tactical/catalogue.h"
#include "tactical/execution_level.h"

namespace strata::coral {
namespace {

namespace fs = std::filesystem;

const fs::path kRoot = fs::path(STRATA_SOURCE_DIR) / "tests" / "coral";

std::vector<std::string> files(const fs::path& dir, const std::string& prefix) {
  std::vector<std::string> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::string name = e.path().filename().string();
    if (e.is_regular_file() && e.path().extension() == ".coral" && name.starts_with(prefix)) {
      out.push_back(e.path().string());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string s = fs::path(info.param).stem().string();
  for (char& c : s) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return s;
}

struct Run {
  core::SourceManager sources;
  core::DiagnosticSink sink;  // the limit strata check uses
  std::optional<Program> program;
};

// Primitives are checked against the built-in catalogue plus the test
// primitives of tests/coral/catalogue.toml, for a vehicle at `level`.
CheckOptions combined_options(tactical::ExecutionLevel level) {
  auto extra = tactical::Catalogue::load((kRoot / "catalogue.toml").string());
  if (!extra) throw std::runtime_error(extra.error().message);
  CheckOptions builtin = strategic::coral_check_options(tactical::Catalogue::builtin(), level);
  CheckOptions tests = strategic::coral_check_options(extra.value(), level);
  CheckOptions both;
  both.primitive = [builtin, tests](std::string_view name) {
    auto found = tests.primitive(name);
    return found ? found : builtin.primitive(name);
  };
  both.primitive_names = builtin.primitive_names;
  both.primitive_names.insert(both.primitive_names.end(), tests.primitive_names.begin(), tests.primitive_names.end());
  both.execution_level = builtin.execution_level;
  return both;
}

const CheckOptions& check_options(tactical::ExecutionLevel level = tactical::ExecutionLevel::Phoenix) {
  static const CheckOptions phoenix = combined_options(tactical::ExecutionLevel::Phoenix);
  static const CheckOptions imc = combined_options(tactical::ExecutionLevel::Imc);
  return level == tactical::ExecutionLevel::Imc ? imc : phoenix;
}

std::unique_ptr<Run> compile(const std::string& path,
                             tactical::ExecutionLevel level = tactical::ExecutionLevel::Phoenix) {
  auto r = std::make_unique<Run>();
  DiskFileProvider disk;
  r->program = compile_file(path, disk, r->sources, r->sink, check_options(level));
  r->sink.sort();
  return r;
}

std::string printed(const Run& r) {
  std::ostringstream out;
  core::print_diagnostics(out, r.sources, r.sink.diagnostics());
  return out.str();
}

class OkFile : public ::testing::TestWithParam<std::string> {};

TEST_P(OkFile, CompilesCleanlyAndMatchesItsGoldenDump) {
  const std::string& path = GetParam();
  auto r = compile(path);
  ASSERT_TRUE(r->program) << printed(*r);
  EXPECT_EQ(0u, r->sink.diagnostics().size()) << printed(*r);
  std::string dump = dump_program(*r->program);
  fs::path golden = fs::path(path).replace_extension(".dump");
  if (std::getenv("STRATA_UPDATE_GOLDEN")) {
    std::ofstream(golden, std::ios::binary) << dump;
  }
  ASSERT_TRUE(fs::exists(golden)) << "missing golden dump " << golden
                                  << " (run with STRATA_UPDATE_GOLDEN=1 to create it)";
  EXPECT_EQ(read(golden), dump);
}

INSTANTIATE_TEST_SUITE_P(Coral, OkFile, ::testing::ValuesIn(files(kRoot / "ok", "")), test_name);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(OkFile);

class FailFile : public ::testing::TestWithParam<std::string> {};

TEST_P(FailFile, ReportsExactlyTheAnnotatedDiagnostics) {
  const std::string& path = GetParam();
  std::vector<std::string> expected;
  static const std::regex annotation(R"(//\s*(error|warning):\s*([^\s:]+:)?(\d+):(\d+)\s*\[(\w+)\])");
  std::string text = read(path);
  for (std::sregex_iterator it(text.begin(), text.end(), annotation), end; it != end; ++it) {
    expected.push_back(
        fmt::format("{} {}{}:{} [{}]", (*it)[1].str(), (*it)[2].str(), (*it)[3].str(), (*it)[4].str(), (*it)[5].str()));
  }
  ASSERT_FALSE(expected.empty()) << path << " has no // error: or // warning: annotation";
  static const std::regex vehicle(R"(//\s*vehicle:\s*(\S+))");
  std::smatch m;
  auto r = compile(path, std::regex_search(text, m, vehicle) ? tactical::execution_level_of(m[1].str())
                                                             : tactical::ExecutionLevel::Phoenix);
  std::vector<std::string> got;
  const fs::path dir = fs::path(path).parent_path();
  for (const auto& d : r->sink.diagnostics()) {
    if (d.span.file >= r->sources.size()) {
      got.push_back(fmt::format("{} ? [{}]", core::severity_name(d.severity), core::kind_name(d.kind)));
      continue;
    }
    const std::string& where = r->sources.path(d.span.file);
    std::string prefix = where == path ? "" : fs::path(where).lexically_relative(dir).generic_string() + ":";
    auto lc = r->sources.line_col(d.span.file, d.span.offset);
    got.push_back(fmt::format("{} {}{}:{} [{}]", core::severity_name(d.severity), prefix, lc.line, lc.col,
                              core::kind_name(d.kind)));
  }
  std::sort(expected.begin(), expected.end());
  std::sort(got.begin(), got.end());
  EXPECT_EQ(expected, got) << printed(*r);
}

INSTANTIATE_TEST_SUITE_P(Coral, FailFile, ::testing::ValuesIn(files(kRoot, "fail_")), test_name);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(FailFile);

// Every ```coral block of docs/language.md checks without a diagnostic, with
// the catalogue the language tests use (an `import "lib/X.coral"` reads
// tests/coral/ok/lib/X.coral, `import "missions/tank/X.coral"` the shipped
// missions/tank/X.coral). The example of phase parameters says it runs
// with the built-in catalogue alone: so it must check with that alone.
TEST(DocsExamples, EveryCoralBlockOfTheLanguageReferenceChecksClean) {
  const std::string doc = read(fs::path(STRATA_SOURCE_DIR) / "docs" / "language.md");
  const std::string open = "```coral\n", close = "```";
  std::size_t count = 0;
  for (std::size_t at = doc.find(open); at != std::string::npos; at = doc.find(open, at)) {
    at += open.size();
    const std::size_t stop = doc.find(close, at);
    ASSERT_NE(std::string::npos, stop) << "an unclosed ```coral block";
    const std::string text = doc.substr(at, stop - at);
    at = stop + close.size();
    ++count;
    auto check_with = [&](const CheckOptions& options) {
      MemoryFileProvider provider;
      provider.add("docs/example.coral", text);
      for (const auto& lib : files(kRoot / "ok" / "lib", "")) {
        provider.add("docs/lib/" + fs::path(lib).filename().string(), read(lib));
      }
      // The import example names the tank mission's phase, relative to a
      // file beside missions/.
      for (const auto& phase : files(fs::path(STRATA_SOURCE_DIR) / "missions" / "tank", "")) {
        if (phase.ends_with(".coral"))
          provider.add("docs/missions/tank/" + fs::path(phase).filename().string(), read(phase));
      }
      core::SourceManager sources;
      core::DiagnosticSink sink;
      auto program = compile_file("docs/example.coral", provider, sources, sink, options);
      std::ostringstream out;
      core::print_diagnostics(out, sources, sink.diagnostics());
      EXPECT_TRUE(program && sink.diagnostics().empty()) << "example " << count << ":\n" << text << out.str();
    };
    check_with(check_options());
    if (text.find("net turn_and_hold") != std::string::npos) {
      check_with(strategic::coral_check_options(tactical::Catalogue::builtin()));
    }
  }
  EXPECT_GE(count, 14u) << "the examples of docs/language.md were not found";
}

}  // namespace
}  // namespace strata::coral
