// `import NAME;`: the phase library's search path and how its modules are
// read (docs/library.md).
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>

#include "coral/compiler.h"
#include "coral/loader.h"

namespace strata::coral {
namespace {

namespace fs = std::filesystem;

constexpr const char* kPhase =
    "net goto(x) { place s = 1; exit arrived; "
    "transition t { wait { s } action { TACTIC(EXEC, sleep(x), arrived) } } }";

struct Loaded {
  core::SourceManager sources;
  core::DiagnosticSink sink;
  Load load;
  std::optional<Program> program;

  std::vector<std::string> kinds() const {
    std::vector<std::string> out;
    for (const auto& d : sink.diagnostics()) {
      std::string where = "?";
      if (d.span.file < sources.size()) {
        auto lc = sources.line_col(d.span.file, d.span.offset);
        where = sources.path(d.span.file) + ":" + std::to_string(lc.line) + ":" + std::to_string(lc.col);
      }
      out.push_back(where + " " + std::string(core::kind_name(d.kind)));
    }
    return out;
  }
};

// main.coral from `mission` (the load's own files), the library from `library`.
std::unique_ptr<Loaded> load_with(const MemoryFileProvider& mission, const Library& library) {
  auto l = std::make_unique<Loaded>();
  l->load = load("main.coral", mission, l->sources, l->sink, library);
  if (!l->sink.has_errors()) l->program = compile(l->load, l->sink);
  return l;
}

TEST(LibraryImport, TakesTheModuleFromTheFirstFolderThatHasIt) {
  MemoryFileProvider mission, lib;
  mission.add("main.coral",
              "import goto;\nmission m { place a = 1; exit e;\n"
              "transition t { wait { a } action { PHASE(goto(2), e) } } }");
  lib.add("mine/goto.coral", std::string(kPhase) + " net from_mine { }");
  lib.add("std/goto.coral", std::string(kPhase) + " net from_std { }");
  auto l = load_with(mission, {{"empty", "mine", "std"}, &lib});
  ASSERT_TRUE(l->program) << ::testing::PrintToString(l->kinds());
  ASSERT_EQ(2u, l->load.files.size());
  EXPECT_EQ("mine/goto.coral", l->load.files[1].path);
  EXPECT_TRUE(l->load.files[1].library);
  EXPECT_FALSE(l->load.files[0].library);
  EXPECT_EQ(3u, l->program->nets.size());  // goto, from_mine and m
}

TEST(LibraryImport, ModulesAreReadThroughTheLibraryNotTheLoadsProvider) {
  // The load's provider has a goto.coral beside the mission: a named import
  // never reads it (a name is not a path), and the studio's sandbox never
  // sees the library's files.
  MemoryFileProvider mission, lib;
  mission.add("main.coral", "import goto;");
  mission.add("std/goto.coral", "this would not parse");
  lib.add("std/goto.coral", kPhase);
  auto l = load_with(mission, {{"std"}, &lib});
  EXPECT_TRUE(l->program) << ::testing::PrintToString(l->kinds());
}

TEST(LibraryImport, AnUnknownNameIsAnErrorAtTheImportNamingTheFolders) {
  MemoryFileProvider mission, lib;
  mission.add("main.coral", "\nimport gotoo;");
  lib.add("std/goto.coral", kPhase);
  auto l = load_with(mission, {{"/opt/lib", "std"}, &lib});
  EXPECT_EQ((std::vector<std::string>{"main.coral:2:1 UnknownModule"}), l->kinds());
  ASSERT_EQ(1u, l->sink.diagnostics().size());
  EXPECT_EQ("no library module 'gotoo': gotoo.coral is in none of the library's folders (/opt/lib, std)",
            l->sink.diagnostics()[0].message);
  auto none = load_with(mission, {{}, &lib});
  ASSERT_EQ(1u, none->sink.diagnostics().size());
  EXPECT_EQ("no library module 'gotoo': gotoo.coral is in none of the library's folders (there are none)",
            none->sink.diagnostics()[0].message);
}

TEST(LibraryImport, AModuleImportedTwiceLoadsOnce) {
  MemoryFileProvider mission, lib;
  mission.add("main.coral", "import goto; import patrol; import goto;");
  lib.add("std/goto.coral", kPhase);
  lib.add("std/patrol.coral",
          "import goto;\nnet patrol { place s = 1; exit done; "
          "transition t { wait { s } action { PHASE(goto(1), done) } } }");
  auto l = load_with(mission, {{"std"}, &lib});
  ASSERT_TRUE(l->program) << ::testing::PrintToString(l->kinds());
  EXPECT_EQ(3u, l->load.files.size());
  EXPECT_EQ(2u, l->program->nets.size());
}

TEST(LibraryImport, ACycleThroughTheLibraryIsReported) {
  MemoryFileProvider mission, lib;
  mission.add("main.coral", "import a;");
  lib.add("std/a.coral", "import b;");
  lib.add("std/b.coral", "\nimport a;");
  auto l = load_with(mission, {{"std"}, &lib});
  EXPECT_EQ((std::vector<std::string>{"std/b.coral:2:1 ImportCycle"}), l->kinds());
}

TEST(LibraryImport, AQuotedImportInAModuleStaysInItsLibraryFolder) {
  MemoryFileProvider mission, lib;
  mission.add("main.coral", "import a;");
  lib.add("std/a.coral", "import \"parts/b.coral\";\nimport \"../secret.coral\";");
  lib.add("std/parts/b.coral", kPhase);
  lib.add("secret.coral", "net secret { }");
  auto l = load_with(mission, {{"std"}, &lib});
  EXPECT_EQ((std::vector<std::string>{"std/a.coral:2:1 FileUnreadable"}), l->kinds());
  ASSERT_EQ(3u, l->load.files.size());
  EXPECT_EQ("std/parts/b.coral", l->load.files[2].path);
  EXPECT_TRUE(l->load.files[2].library);
}

TEST(LibraryImport, ANameIsParsedAsAModuleAndAStringAsAPath) {
  MemoryFileProvider mission, lib;
  mission.add("main.coral", "import \"goto\";");
  lib.add("std/goto.coral", kPhase);
  auto l = load_with(mission, {{"std"}, &lib});
  EXPECT_EQ((std::vector<std::string>{"main.coral:1:1 FileUnreadable"}), l->kinds());
}

TEST(LibraryDirs, EnvironmentFoldersComeFirstThenStratasOwn) {
  EXPECT_EQ((std::vector<std::string>{"/a", "rel/b", std::string(STRATA_SOURCE_DIR) + "/library/coral"}),
            library_dirs("coral", "/a::rel/b:", ""));
  EXPECT_EQ((std::vector<std::string>{std::string(STRATA_SOURCE_DIR) + "/library/prolog"}),
            library_dirs("prolog", nullptr, ""));
  EXPECT_EQ((std::vector<std::string>{std::string(STRATA_SOURCE_DIR) + "/library/coral"}),
            library_dirs("coral", "", "/no/such/bin/strata"));
}

TEST(LibraryDirs, AnInstalledStrataUsesTheLibraryBesideIt) {
  const fs::path root = fs::temp_directory_path() / ("strata_library_dirs_" + std::to_string(::getpid()));
  fs::create_directories(root / "usr/bin");
  fs::create_directories(root / "usr/share/strata/library/coral");
  EXPECT_EQ((std::vector<std::string>{"/mine", (root / "usr/share/strata/library/coral").string()}),
            library_dirs("coral", "/mine", root / "usr/bin/strata"));
  // Without library/prolog there, the source tree's.
  EXPECT_EQ((std::vector<std::string>{std::string(STRATA_SOURCE_DIR) + "/library/prolog"}),
            library_dirs("prolog", nullptr, root / "usr/bin/strata"));
  fs::remove_all(root);
}

TEST(LibraryDirs, EveryShippedModuleLoadsFromStratasOwnLibrary) {
  // Each library/coral/NAME.coral declares the phase net NAME, and loads
  // by name through the standard library (the disk).
  for (const auto& e : fs::directory_iterator(fs::path(STRATA_SOURCE_DIR) / "library" / "coral")) {
    const std::string name = e.path().stem().string();
    MemoryFileProvider mission;
    mission.add("main.coral", "import " + name + ";");
    auto l = load_with(mission, standard_library());
    ASSERT_TRUE(l->program) << name << ": " << ::testing::PrintToString(l->kinds());
    ASSERT_EQ(1u, l->program->nets.size()) << name;
    EXPECT_EQ(name, l->program->nets[0].name);
    EXPECT_TRUE(l->load.files[1].library);
  }
}

}  // namespace
}  // namespace strata::coral
