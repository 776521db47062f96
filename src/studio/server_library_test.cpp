// The studio and the phase library (docs/library.md): a mission of the
// folder that imports a library module by name is read, drawn, checked and
// run, the module being read outside the folder, read-only; the studio
// never writes a library module.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "studio/server.h"
#include "studio/server_test_support.h"

namespace strata::studio {
namespace {

const fs::path kGoto = fs::path(STRATA_SOURCE_DIR) / "library/coral/goto.coral";

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST_F(StudioServerTest, AMissionImportingALibraryModuleIsDrawnCheckedAndRun) {
  std::ofstream(base_ / "root/tank/out.coral")
      << "import goto;\nmission out { place a = 1; exit e;\n"
         "transition go { wait { a } action { PHASE(goto(3, 2, 1, 0.5), e) } } }\n";
  auto c = client();
  auto r = c.Get("/api/mission?path=tank/out.coral");
  ASSERT_TRUE(r);
  ASSERT_EQ(200, r->status) << r->body;
  json m = json::parse(r->body);
  EXPECT_TRUE(m["diagnostics"].empty()) << m["diagnostics"].dump();
  ASSERT_EQ(2u, m["nets"].size()) << m["nets"].dump();
  const json& lib = m["nets"][1];
  EXPECT_EQ("goto", lib["name"]);
  EXPECT_FALSE(lib["editable"].get<bool>());
  EXPECT_EQ(kGoto.string(), lib["file"]);  // its own path, not one through ../..

  auto run = c.Post("/api/run", R"({"path": "tank/out.coral"})", "application/json");
  ASSERT_TRUE(run);
  EXPECT_EQ(202, run->status) << run->body;
  EXPECT_EQ(1u, runs_.size());
}

TEST_F(StudioServerTest, LibraryMistakesAreShownAtTheImportOrTheModulesOwnPath) {
  // An unknown module names the folders searched, at the import.
  json body = {{"path", "tank/tank.coral"}, {"text", "import no_such_phase;\nmission m { place a = 1; exit e; }\n"}};
  auto c = client();
  auto r = c.Post("/api/check", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(200, r->status) << r->body;
  json m = json::parse(r->body);
  ASSERT_EQ(1u, m["diagnostics"].size()) << m.dump();
  EXPECT_EQ("UnknownModule", m["diagnostics"][0]["kind"]);
  EXPECT_EQ("tank/tank.coral", m["diagnostics"][0]["file"]);
  // A mistake inside a library module (here: a phase called with a number
  // out of range) points into the module, shown at its own path.
  body["text"] =
      "import goto;\nmission m { place a = 1; exit e;\n"
      "transition go { wait { a } action { PHASE(goto(1, 2, 99, 0.5), e) } } }\n";
  r = c.Post("/api/check", body.dump(), "application/json");
  ASSERT_TRUE(r);
  m = json::parse(r->body);
  ASSERT_FALSE(m["diagnostics"].empty()) << m.dump();
  EXPECT_EQ("ArgumentOutOfRange", m["diagnostics"][0]["kind"]);
  bool noted_in_module = false;
  for (const auto& n : m["diagnostics"][0]["notes"]) noted_in_module |= n.value("file", "") == kGoto.string();
  EXPECT_TRUE(noted_in_module) << m["diagnostics"].dump();
}

TEST_F(StudioServerTest, NeverWritesALibraryModule) {
  const std::string before = bytes_of(kGoto);
  ASSERT_FALSE(before.empty());
  auto c = client();
  const std::string rel = fs::path(kGoto).lexically_relative(base_ / "root").generic_string();
  for (const std::string& path : {kGoto.string(), rel}) {
    auto put = c.Put("/api/file?path=" + path, "net goto { }", "text/plain");
    ASSERT_TRUE(put) << path;
    EXPECT_EQ(403, put->status) << path << ": " << put->body;
    auto layout = c.Put("/api/layout?path=" + path, R"({"goto": {}})", "application/json");
    ASSERT_TRUE(layout) << path;
    EXPECT_EQ(403, layout->status) << path << ": " << layout->body;
  }
  EXPECT_EQ(before, bytes_of(kGoto));
  EXPECT_FALSE(fs::exists(kGoto.string() + ".layout.json"));
}

}  // namespace
}  // namespace strata::studio
