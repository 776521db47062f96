#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "coral/lexer.h"
#include "coral/loader.h"
#include "coral/test_support.h"
#include "core/test_fifo.h"

namespace strata::coral {
namespace {

using testing::compile_text;

TEST(Loader, ImportsResolveAgainstTheImportingFile) {
  auto c = compile_text(
      "import \"lib/a.coral\";\nmission m { place s = 1; exit e;\n"
      "transition t { wait { s } action { PHASE(pa, e) } } }",
      {{"lib/a.coral",
        "import \"b.coral\";\nnet pa { place s = 1; exit e; "
        "transition t { wait { s } action { PHASE(pb, e) } } }"},
       {"lib/b.coral", "net pb { place s = 1; exit e; transition t { wait { s } signal { e } } }"}});
  EXPECT_TRUE(c->program) << ::testing::PrintToString(c->kinds());
  EXPECT_EQ(3u, c->program->nets.size());
}

TEST(Loader, DiamondImportLoadsOnce) {
  auto c = compile_text("import \"a.coral\"; import \"b.coral\";",
                        {{"a.coral", "import \"c.coral\";"},
                         {"b.coral", "import \"./c.coral\";"},
                         {"c.coral", "net shared { place s = 1; exit e; transition t { wait { s } signal { e } } }"}});
  ASSERT_TRUE(c->program) << ::testing::PrintToString(c->kinds());
  EXPECT_EQ(1u, c->program->nets.size());
}

TEST(Loader, CycleIsReportedAtTheClosingImport) {
  auto c =
      compile_text("import \"a.coral\";", {{"a.coral", "import \"b.coral\";"}, {"b.coral", "\n import \"a.coral\";"}});
  EXPECT_FALSE(c->program);
  ASSERT_EQ(1u, c->sink.diagnostics().size());
  const auto& d = c->sink.diagnostics()[0];
  EXPECT_EQ(core::DiagnosticKind::ImportCycle, d.kind);
  EXPECT_EQ("b.coral", c->sources.path(d.span.file));
  EXPECT_EQ(2u, c->sources.line_col(d.span.file, d.span.offset).line);
}

TEST(Loader, MissingImportIsUnreadableAtTheImport) {
  auto c = compile_text("\nimport \"gone.coral\";");
  EXPECT_EQ((std::vector<std::string>{"2:1 FileUnreadable"}), c->kinds());
}

TEST(Loader, SelfImportIsACycle) {
  auto c = compile_text("import \"main.coral\";");
  EXPECT_EQ((std::vector<std::string>{"1:1 ImportCycle"}), c->kinds());
}

TEST(Loader, OversizedFileIsReportedNotParsed) {
  auto c = compile_text("import \"big.coral\";", {{"big.coral", std::string(kMaxSourceSize + 1, ' ')}});
  EXPECT_EQ((std::vector<std::string>{"1:1 FileTooLarge"}), c->kinds());
}

TEST(Loader, AFifoGivenAsASourceIsAnErrorNotAHang) {
  const auto fifo = core::testing::make_fifo("mission.coral");
  ASSERT_FALSE(fifo.empty());
  DiskFileProvider disk;
  auto r = disk.read(fifo.string());
  std::filesystem::remove_all(fifo.parent_path());
  ASSERT_FALSE(r);
  EXPECT_EQ(core::ErrorCode::Io, r.error().code);
  EXPECT_NE(r.error().message.find("not a regular file"), std::string::npos) << r.error().message;
}

// A mission's folder could have `strata check` show any readable file's
// lines in its syntax errors: `import "/etc/passwd";`, or a link
// `phases.coral -> ~/.ssh/id_rsa` (and CI puts those errors in its log).
// An import now reads CORAL files only, by the name they have once links
// are resolved; a link to a CORAL file elsewhere still loads.
class LoaderOnDisk : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/strata_loader_XXXXXX";
    ASSERT_NE(nullptr, ::mkdtemp(tmpl));
    dir_ = tmpl;
    std::filesystem::create_directories(dir_ / "mission");
    std::ofstream(dir_ / "secret.txt") << "TOKEN=abc123 do not show\n";
    std::ofstream(dir_ / "shared.coral")
        << "net shared { place s = 1; exit e; transition t { wait { s } signal { e } } }\n";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // The diagnostics of loading mission/m.coral, which imports `import`.
  std::vector<core::Diagnostic> load_importing(const std::string& import) {
    std::ofstream(dir_ / "mission/m.coral") << "import \"" << import << "\";\n";
    DiskFileProvider disk;
    core::SourceManager sources;
    core::DiagnosticSink sink;
    load((dir_ / "mission/m.coral").string(), disk, sources, sink);
    for (core::FileId f = 0; f < sources.size(); ++f) {
      EXPECT_EQ(std::string::npos, sources.text(f).find("TOKEN")) << "read: " << sources.path(f);
    }
    return sink.diagnostics();
  }

  std::filesystem::path dir_;
};

TEST_F(LoaderOnDisk, AnImportOfAFileThatIsNotCoralIsRefusedUnread) {
  for (const std::string& import : {(dir_ / "secret.txt").string(), std::string("../secret.txt")}) {
    const auto d = load_importing(import);
    ASSERT_EQ(1u, d.size()) << import;
    EXPECT_EQ(core::DiagnosticKind::FileUnreadable, d[0].kind);
    EXPECT_NE(std::string::npos, d[0].message.find("is not a CORAL file (.coral)")) << d[0].message;
  }
}

TEST_F(LoaderOnDisk, AnImportThroughALinkToAFileThatIsNotCoralIsRefusedUnreadNamingTheTarget) {
  std::filesystem::create_symlink(dir_ / "secret.txt", dir_ / "mission/phases.coral");
  const auto d = load_importing("phases.coral");
  ASSERT_EQ(1u, d.size());
  EXPECT_EQ(core::DiagnosticKind::FileUnreadable, d[0].kind);
  EXPECT_NE(std::string::npos, d[0].message.find("is a link to '" + (dir_ / "secret.txt").string() + "'"))
      << d[0].message;
}

TEST_F(LoaderOnDisk, AnImportThroughALinkToACoralFileLoads) {
  std::filesystem::create_symlink(dir_ / "shared.coral", dir_ / "mission/linked.coral");
  EXPECT_TRUE(load_importing("linked.coral").empty());
  EXPECT_TRUE(load_importing("../shared.coral").empty());
}

TEST_F(LoaderOnDisk, AFolderNamedAsACoralFileIsNotRead) {
  std::filesystem::create_directories(dir_ / "mission/dir.coral");
  const auto d = load_importing("dir.coral");
  ASSERT_EQ(1u, d.size());
  EXPECT_EQ(core::DiagnosticKind::FileUnreadable, d[0].kind);
  EXPECT_NE(std::string::npos, d[0].message.find("not a regular file")) << d[0].message;
}

TEST(Loader, AMissingSourceSaysCannotOpen) {
  DiskFileProvider disk;
  auto r = disk.read("/nonexistent/strata/mission.coral");
  ASSERT_FALSE(r);
  EXPECT_EQ(core::ErrorCode::Io, r.error().code);
  EXPECT_EQ("cannot open '/nonexistent/strata/mission.coral': No such file or directory", r.error().message);
}

}  // namespace
}  // namespace strata::coral
