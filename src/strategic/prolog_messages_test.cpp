#include "strategic/prolog_messages.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "core/diagnostic_printer.h"

namespace strata::strategic {
namespace {

namespace fs = std::filesystem;

class PrologMessages : public ::testing::Test {
 protected:
  PrologMessages() {
    dir_ = fs::temp_directory_path() /
           ("strata_prolog_messages_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(dir_);
    path_ = (dir_ / "m.pl").string();
    std::ofstream(path_) << "mission :-\n    exec_warp(1, X),\n    X == 1.\n";
  }
  ~PrologMessages() override { fs::remove_all(dir_); }

  std::string printed(const std::vector<PrologMessage>& messages) {
    report_messages(messages, 1u << 20, sources_, sink_);
    std::ostringstream out;
    core::print_diagnostics(out, sources_, sink_.diagnostics());
    return out.str();
  }

  fs::path dir_;
  std::string path_;
  core::SourceManager sources_;
  core::DiagnosticSink sink_;
};

TEST_F(PrologMessages, AMessageWithLineAndColumnShowsTheLineAndACaret) {
  EXPECT_EQ(
      path_ +
          ":2:5: error: exec_warp/2: `warp` is not an exec primitive [PrologCheckError]\n"
          "       exec_warp(1, X),\n"
          "       ^\n",
      printed({{core::DiagnosticKind::PrologCheckError, path_, 2, 5, "exec_warp/2: `warp` is not an exec primitive"}}));
  auto j = core::diagnostics_to_json(sources_, sink_.diagnostics());
  EXPECT_EQ(2, j[0]["line"]);
  EXPECT_EQ(5, j[0]["col"]);
  EXPECT_EQ("PrologCheckError", j[0]["kind"]);
  EXPECT_EQ("error", j[0]["severity"]);
}

TEST_F(PrologMessages, AMessageWithoutColumnShowsItsLineAndNoColumn) {
  EXPECT_EQ(path_ +
                ":3: warning: Singleton variables: [X] [PrologLoadWarning]\n"
                "       X == 1.\n",
            printed({{core::DiagnosticKind::PrologLoadWarning, path_, 3, 0, "Singleton variables: [X]"}}));
  EXPECT_EQ(1u, sink_.warning_count());
  auto j = core::diagnostics_to_json(sources_, sink_.diagnostics());
  EXPECT_EQ(3, j[0]["line"]);
  EXPECT_FALSE(j[0].contains("col"));
  EXPECT_FALSE(j[0].contains("end_line"));
}

TEST_F(PrologMessages, AMessageWithoutLineNamesItsFileAlone) {
  EXPECT_EQ(path_ + ": error: loading took longer than its time limit [PrologLoadError]\n",
            printed({{core::DiagnosticKind::PrologLoadError, path_, 0, 0, "loading took longer than its time limit"}}));
  auto j = core::diagnostics_to_json(sources_, sink_.diagnostics());
  EXPECT_EQ(path_, j[0]["file"]);
  EXPECT_FALSE(j[0].contains("line"));
}

TEST_F(PrologMessages, AFileThatCannotBeReadAgainIsNamedWithoutItsLine) {
  const std::string gone = (dir_ / "gone.pl").string();
  EXPECT_EQ(gone + ": error: syntax error [PrologLoadError]\n",
            printed({{core::DiagnosticKind::PrologLoadError, gone, 4, 2, "syntax error"}}));
}

TEST_F(PrologMessages, AMessageWithoutFileHasNoPlace) {
  EXPECT_EQ("strata: error: failed [PrologCheckError]\n",
            printed({{core::DiagnosticKind::PrologCheckError, "", 0, 0, "failed"}}));
}

TEST_F(PrologMessages, AColumnPastItsLineIsTheLineEnd) {
  printed({{core::DiagnosticKind::PrologLoadError, path_, 1, 99, "end of clause expected"},
           {core::DiagnosticKind::PrologLoadError, path_, 9, 1, "past the last line"}});
  ASSERT_EQ(2u, sink_.diagnostics().size());
  EXPECT_EQ(1u, sources_.size()) << "each file once";
  auto first = sources_.line_col(sink_.diagnostics()[0].span.file, sink_.diagnostics()[0].span.offset);
  EXPECT_EQ(1u, first.line);
  EXPECT_EQ(11u, first.col);  // "mission :-" has 10 bytes
  auto second = sources_.line_col(sink_.diagnostics()[1].span.file, sink_.diagnostics()[1].span.offset);
  EXPECT_EQ(4u, second.line);  // the empty line after the last newline
}

}  // namespace
}  // namespace strata::strategic
