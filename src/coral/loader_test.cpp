#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
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

TEST(Loader, AMissingSourceSaysCannotOpen) {
  DiskFileProvider disk;
  auto r = disk.read("/nonexistent/strata/mission.coral");
  ASSERT_FALSE(r);
  EXPECT_EQ(core::ErrorCode::Io, r.error().code);
  EXPECT_EQ("cannot open '/nonexistent/strata/mission.coral': No such file or directory", r.error().message);
}

}  // namespace
}  // namespace strata::coral
