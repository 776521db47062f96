// The studio server over loopback: the JSON API and the folder it may not
// leave (its limits: server_limits_test.cpp; streams: server_stream_test.cpp).
#include "studio/server.h"

#include <stdlib.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>

#include "studio/server_test_support.h"
#include "studio/sonar_status.h"

namespace strata::studio {
namespace {

TEST_F(StudioServerTest, ServesTheNewestSonarScanOnceThereIsOne) {
  auto c = client();
  auto none = c.Get("/api/sonar");
  ASSERT_TRUE(none);
  json j = json::parse(none->body);
  EXPECT_TRUE(j["dir"].get<bool>());
  EXPECT_TRUE(j["latest"].is_null());
  EXPECT_EQ(404, c.Get("/api/sonar/latest.png")->status);

  fs::create_directories(base_ / "sonar");
  const std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + "not really an image";
  std::ofstream(base_ / "sonar/latest.png", std::ios::binary) << png;
  // Two whole frame lines and one being written: the last whole one counts.
  std::ofstream(base_ / "sonar/sonar.jsonl") << "{\"event\":\"frame\",\"frame\":1}\n{\"event\":\"frame\",\"frame\":2,"
                                                "\"target\":null}\n{\"event\":\"frame\",\"frame\":3,";
  auto some = c.Get("/api/sonar");
  j = json::parse(some->body);
  EXPECT_EQ(png.size(), j["latest"]["bytes"].get<std::size_t>());
  EXPECT_EQ(2, j["frame"]["frame"]);
  auto image = c.Get("/api/sonar/latest.png");
  EXPECT_EQ(200, image->status);
  EXPECT_EQ("image/png", image->get_header_value("Content-Type"));
  EXPECT_EQ(png, image->body);
}

TEST(SonarStatus, NoFolderMeansNoSonar) {
  const json j = sonar_status({});
  EXPECT_FALSE(j["dir"].get<bool>());
  EXPECT_TRUE(j["latest"].is_null());
}

TEST_F(StudioServerTest, ListsTheMissionsAndServesTheirModel) {
  auto c = client();
  auto files = c.Get("/api/files");
  ASSERT_TRUE(files);
  EXPECT_EQ(200, files->status);
  json j = json::parse(files->body);
  EXPECT_NE(j["files"].end(), std::find(j["files"].begin(), j["files"].end(), "tank/tank.coral")) << j.dump();

  auto mission = c.Get("/api/mission?path=tank/tank.coral");
  ASSERT_TRUE(mission);
  ASSERT_EQ(200, mission->status) << mission->body;
  json m = json::parse(mission->body);
  ASSERT_EQ(5u, m["nets"].size());
  const json& tank = m["nets"][0];  // the root file's nets come first
  EXPECT_EQ("tank", tank["name"]);
  EXPECT_EQ("mission", tank["kind"]);
  EXPECT_TRUE(tank["editable"].get<bool>());
  EXPECT_EQ("initialize", m["nets"][1]["name"]);
  EXPECT_FALSE(m["nets"][1]["editable"].get<bool>());  // an import
  EXPECT_EQ("tank/initialize.coral", m["nets"][1]["file"]);
  EXPECT_EQ("PHASE initialize", tank["transitions"][0]["actions"][0]["label"]);
  EXPECT_EQ(json::array({"initialized", "aborted"}), tank["transitions"][0]["actions"][0]["outcomes"]);
  EXPECT_EQ(12, tank["places"][0]["line"]);  // `place begin = 1;`
  EXPECT_TRUE(m["diagnostics"].empty());
}

// Issue 39: a file whose name is not UTF-8 was listed (mangled in JSON)
// and then could not be opened (404). Left out of the lists, and counted.
TEST_F(StudioServerTest, AFileNamedInNoUtf8IsNotListedButCounted) {
  std::ofstream(base_ / "root/tank/caf\xe9.coral") << "net n { }\n";
  auto files = client().Get("/api/files");
  ASSERT_TRUE(files);
  ASSERT_EQ(200, files->status);
  const json j = json::parse(files->body);
  for (const char* list : {"files", "missions"}) {
    for (const auto& f : j[list]) {
      const std::string path = f.is_string() ? f.get<std::string>() : f["path"].get<std::string>();
      EXPECT_EQ(std::string::npos, path.find("caf")) << path;
    }
  }
  ASSERT_TRUE(j.contains("unlisted")) << j.dump();
  EXPECT_EQ("1 file whose name is not UTF-8 (rename to open in the studio)", j["unlisted"]);
}

TEST_F(StudioServerTest, ChecksUnsavedTextAndPointsAtTheLine) {
  auto c = client();
  json body = {{"path", "tank/tank.coral"}, {"text", "mission m { place a = 1;\n transition t { wait { b } } }"}};
  auto r = c.Post("/api/check", body.dump(), "application/json");
  ASSERT_TRUE(r);
  json m = json::parse(r->body);
  EXPECT_TRUE(m["nets"].empty());
  ASSERT_FALSE(m["diagnostics"].empty());
  EXPECT_EQ("UndefinedPlace", m["diagnostics"][0]["kind"]) << m["diagnostics"].dump();
  EXPECT_EQ("tank/tank.coral", m["diagnostics"][0]["file"]);
}

TEST_F(StudioServerTest, RefusesPathsThatLeaveTheFolder) {
  fs::create_symlink(base_ / "secret.coral", base_ / "root/link.coral");
  auto c = client();
  for (const char* path : {"/api/mission?path=../secret.coral", "/api/mission?path=%2e%2e%2fsecret.coral",
                           "/api/mission?path=tank%2f..%2f..%2fsecret.coral", "/api/mission?path=/etc/passwd",
                           "/api/mission?path=link.coral"}) {
    auto r = c.Get(path);
    ASSERT_TRUE(r) << path;
    EXPECT_EQ(403, r->status) << path << ": " << r->body;
  }
  auto put = c.Put("/api/file?path=..%2fescape.coral", "net x {}", "text/plain");
  ASSERT_TRUE(put);
  EXPECT_EQ(403, put->status);
  EXPECT_FALSE(fs::exists(base_ / "escape.coral"));
  auto other = c.Put("/api/file?path=tank/setpoints.toml", "x", "text/plain");
  ASSERT_TRUE(other);
  EXPECT_EQ(403, other->status);
}

TEST_F(StudioServerTest, SavesTextAndLayoutInsideTheFolder) {
  auto c = client();
  auto put = c.Put("/api/file?path=tank/new.coral", "net fresh { place a = 1; exit e; }\n", "text/plain");
  ASSERT_TRUE(put);
  EXPECT_EQ(200, put->status) << put->body;
  std::ifstream in(base_ / "root/tank/new.coral");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ("net fresh { place a = 1; exit e; }\n", text);
  auto layout = c.Put("/api/layout?path=tank/new.coral", R"({"fresh": {"a": {"x": 1, "y": 2}}})", "application/json");
  ASSERT_TRUE(layout);
  EXPECT_EQ(200, layout->status);
  auto m = c.Get("/api/mission?path=tank/new.coral");
  ASSERT_TRUE(m);
  EXPECT_EQ(1, json::parse(m->body)["layout"]["fresh"]["a"]["x"]);
}

// Issue 17: `ln -s ../../outside/victim missions/tank/initialize.coral.strata-tmp`,
// then saving initialize.coral, overwrote the victim.
TEST_F(StudioServerTest, SaveDoesNotWriteThroughLinksPlantedInTheFolder) {
  fs::create_directories(base_ / "outside");
  std::ofstream(base_ / "outside/victim") << "precious";
  fs::create_symlink("../../outside/victim", base_ / "root/tank/initialize.coral.strata-tmp");
  fs::create_symlink("../../outside/victim", base_ / "root/tank/linked.coral");
  fs::create_symlink("../../outside/victim", base_ / "root/tank/tank.coral.layout.json");
  auto c = client();
  httplib::Headers match = {{"If-Match", etag_of("tank/initialize.coral")}};
  auto put = c.Put("/api/file?path=tank/initialize.coral", match, "net fresh { place a = 1; exit e; }\n", "text/plain");
  ASSERT_TRUE(put);
  EXPECT_EQ(200, put->status) << put->body;
  EXPECT_EQ("net fresh { place a = 1; exit e; }\n", slurp(base_ / "root/tank/initialize.coral"));
  EXPECT_FALSE(fs::is_symlink(base_ / "root/tank/initialize.coral"));
  // A target that is itself a link out: refused, not followed.
  put = c.Put("/api/file?path=tank/linked.coral", "net x {}", "text/plain");
  ASSERT_TRUE(put);
  EXPECT_EQ(403, put->status) << put->body;
  auto layout = c.Put("/api/layout?path=tank/tank.coral", R"({"tank": {}})", "application/json");
  ASSERT_TRUE(layout);
  EXPECT_EQ(403, layout->status) << layout->body;
  EXPECT_EQ("application/json", layout->get_header_value("Content-Type"));
  EXPECT_EQ("precious", slurp(base_ / "outside/victim"));
}

TEST_F(StudioServerTest, EditsComeBackAsTheNewTextAndItsModel) {
  auto c = client();
  auto mission = c.Get("/api/mission?path=tank/tank.coral");
  ASSERT_TRUE(mission);
  const std::string text = json::parse(mission->body)["text"];
  json body = {{"path", "tank/tank.coral"},
               {"text", text},
               {"op", {{"op", "add_place"}, {"net", "tank"}, {"name", "spare"}, {"initial", 0}}}};
  auto r = c.Post("/api/edit", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(200, r->status) << r->body;
  json m = json::parse(r->body);
  EXPECT_NE(std::string::npos, m["text"].get<std::string>().find("place spare;"));
  // The new place is unused: the checker says so, on its line.
  bool warned = false;
  for (const auto& d : m["diagnostics"]) warned = warned || d["kind"] == "UnusedPlace";
  EXPECT_TRUE(warned) << m["diagnostics"].dump();
  body = {{"path", "tank/tank.coral"},
          {"text", m["text"]},
          {"op",
           {{"op", "set_actions"},
            {"net", "tank"},
            {"transition", "shutdown"},
            {"actions",
             {{{"kind", "TACTIC"}, {"type", "EXEC"}, {"target", "sleep"}, {"args", {"2"}}, {"outcomes", {"spare"}}},
              {{"kind", "TACTIC"}, {"type", "REPORT"}, {"text", "say \"bye\""}}}}}}};
  r = c.Post("/api/edit", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(200, r->status) << r->body;
  EXPECT_NE(std::string::npos,
            json::parse(r->body)["text"].get<std::string>().find(
                "action { TACTIC(EXEC, sleep(2), spare),\n             TACTIC(REPORT, \"say \\\"bye\\\"\") }"))
      << json::parse(r->body)["text"].get<std::string>();
  body["op"] = {{"op", "add_arc"}, {"net", "tank"}, {"from", "begin"}, {"to", "finished"}};
  r = c.Post("/api/edit", body.dump(), "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(400, r->status);
  EXPECT_NE(std::string::npos, r->body.find("joins a place and a transition"));
}

TEST_F(StudioServerTest, VerifiesAndListsPrimitives) {
  auto c = client();
  auto v = c.Post("/api/verify", R"({"path": "tank/tank.coral"})", "application/json");
  ASSERT_TRUE(v);
  ASSERT_EQ(200, v->status) << v->body;
  EXPECT_TRUE(json::parse(v->body)["ok"].get<bool>());
  auto p = c.Get("/api/primitives");
  ASSERT_TRUE(p);
  json prims = json::parse(p->body)["primitives"];
  auto sleep = std::find_if(prims.begin(), prims.end(), [](const json& x) { return x["name"] == "sleep"; });
  ASSERT_NE(prims.end(), sleep);
  EXPECT_EQ("exec", (*sleep)["kind"]);
  EXPECT_EQ("s", (*sleep)["args"][0]["unit"]);
}

TEST_F(StudioServerTest, RunRequestsGoToTheRunner) {
  auto c = client();
  auto r =
      c.Post("/api/run", R"({"path": "tank/tank.coral", "scenario": "leak_phase2", "speed": 20})", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(202, r->status) << r->body;
  ASSERT_EQ(1u, runs_.size());
  EXPECT_EQ("leak_phase2", runs_[0].scenario);
  EXPECT_EQ(20.0, runs_[0].speed);
  auto bad = c.Post("/api/run", R"({"path": "tank/tank.coral", "speed": 0})", "application/json");
  ASSERT_TRUE(bad);
  EXPECT_EQ(400, bad->status);
}

// Issue 17: an import by absolute path quoted /etc/passwd's tokens in the
// diagnostics, and a .coral outside the folder came back whole.
TEST_F(StudioServerTest, ImportsOutsideTheFolderAreRefusedWithoutReadingThem) {
  std::ofstream(base_ / "outside.coral") << "phase leaked { place secret_place = 1; exit done; }\n";
  fs::create_symlink("../outside.coral", base_ / "root/linked.coral");
  auto c = client();
  for (const std::string& import : std::vector<std::string>{"/etc/passwd", "../../outside.coral", "../linked.coral",
                                                            (base_ / "outside.coral").string()}) {
    json body = {{"path", "tank/tank.coral"},
                 {"text", "import \"" + import + "\";\nmission m { place a = 1; exit e; }\n"}};
    auto r = c.Post("/api/check", body.dump(), "application/json");
    ASSERT_TRUE(r);
    ASSERT_EQ(200, r->status) << r->body;
    EXPECT_EQ(std::string::npos, r->body.find("root:")) << import;  // nothing of /etc/passwd
    EXPECT_EQ(std::string::npos, r->body.find("secret_place")) << import;
    EXPECT_EQ(std::string::npos, r->body.find("leaked")) << import;
    json m = json::parse(r->body);
    ASSERT_FALSE(m["diagnostics"].empty()) << import;
    // A file that is no CORAL file is refused before the folder is asked
    // (coral/loader.cpp), for the command line as for the studio.
    const char* why = import == "/etc/passwd" ? "is not a CORAL file (.coral)" : "outside the studio's folder";
    EXPECT_NE(std::string::npos, m["diagnostics"][0]["message"].get<std::string>().find(why))
        << m["diagnostics"].dump();
    EXPECT_EQ(1, m["diagnostics"][0]["line"]) << m["diagnostics"].dump();  // at the import
    EXPECT_EQ("tank/tank.coral", m["diagnostics"][0]["file"]);
  }
  // An import inside still works.
  json body = {{"path", "tank/tank.coral"},
               {"text", "import \"initialize.coral\";\nmission m { place a = 1; exit e; }\n"}};
  auto r = c.Post("/api/check", body.dump(), "application/json");
  ASSERT_TRUE(r);
  EXPECT_NE(std::string::npos, r->body.find("\"initialize\""));
  // A mission that imports outside is not run either.
  std::ofstream(base_ / "root/tank/escape.coral")
      << "import \"../../outside.coral\";\nmission m { place a = 1; exit e; }\n";
  auto run = c.Post("/api/run", R"({"path": "tank/escape.coral"})", "application/json");
  ASSERT_TRUE(run);
  EXPECT_EQ(403, run->status) << run->body;
  EXPECT_TRUE(runs_.empty());
}

// Regression: an import of a FIFO (or any file that never ends) could block
// the worker for ever; it is refused at once, with the import's location.
TEST_F(StudioServerTest, AFifoImportIsRefusedAtOnceByCheckAndVerify) {
  ASSERT_EQ(0, ::mkfifo((base_ / "root/tank/fifo_lib.coral").c_str(), 0600));
  const std::string text =
      "import \"fifo_lib.coral\";\nmission m { place a = 1; exit e; transition t { wait { a } signal { e } } }\n";
  std::ofstream(base_ / "root/tank/imports_fifo.coral") << text;
  auto c = client();
  const auto started = std::chrono::steady_clock::now();
  auto check =
      c.Post("/api/check", json({{"path", "tank/imports_fifo.coral"}, {"text", text}}).dump(), "application/json");
  ASSERT_TRUE(check);
  ASSERT_EQ(200, check->status) << check->body;
  const json diagnostics = json::parse(check->body)["diagnostics"];
  ASSERT_EQ(1u, diagnostics.size()) << check->body;
  EXPECT_EQ("FileUnreadable", diagnostics[0]["kind"]);
  EXPECT_EQ(1, diagnostics[0]["line"]);
  EXPECT_NE(std::string::npos, diagnostics[0]["message"].get<std::string>().find("not a regular file"))
      << diagnostics[0].dump();
  auto verify = c.Post("/api/verify", R"({"path": "tank/imports_fifo.coral"})", "application/json");
  ASSERT_TRUE(verify);
  EXPECT_EQ(422, verify->status) << verify->body;
  EXPECT_NE(std::string::npos, verify->body.find("not a regular file")) << verify->body;
  // A run is not refused as an escape: nothing left the folder (the run's
  // own load reports the FIFO).
  auto run = c.Post("/api/run", R"({"path": "tank/imports_fifo.coral"})", "application/json");
  ASSERT_TRUE(run);
  EXPECT_EQ(std::string::npos, run->body.find("outside the studio's folder")) << run->body;
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(10));
}

TEST_F(StudioServerTest, VerifyResultsCarryTheirLocationInTheFolder) {
  std::ofstream(base_ / "root/tank/dead.coral") << "mission m { place a = 1, never; exit e;\n"
                                                   "  transition t { wait { a } signal { e } }\n"
                                                   "  transition u { wait { never } signal { e } } }\n";
  auto c = client();
  auto v = c.Post("/api/verify", R"({"path": "tank/dead.coral"})", "application/json");
  ASSERT_TRUE(v);
  ASSERT_EQ(200, v->status) << v->body;
  const json r = json::parse(v->body);
  EXPECT_TRUE(r["ok"].get<bool>());  // a dead transition is a warning
  EXPECT_FALSE(r["all_hold"].get<bool>());
  for (const json& p : r["nets"][0]["properties"]) {
    if (p["key"] != "no_dead") continue;
    EXPECT_EQ(json({{"file", "tank/dead.coral"}, {"line", 3}, {"col", 3}, {"transition", "u"}}), p["at"]) << p.dump();
  }
}

// Issue 38: a mission's `require` comes back with its worst path, each step
// with its instance, net and time, for the page to play on the nets.
TEST_F(StudioServerTest, ARequirementComesBackWithItsWorstPathAcrossTheNets) {
  std::ofstream(base_ / "root/tank/held.coral")
      << "net hold(s) { place a = 1; exit done;\n"
         "  transition nap { wait { a } action { TACTIC(EXEC, sleep(s), done) } } }\n"
         "mission held { require \"fault system_problem -> exec surface within 2\";\n"
         "  place begin = 1, held, up; exit closed, aborted;\n"
         "  transition hold { wait { begin } action { PHASE(hold(5), held) } }\n"
         "  transition check { wait { held } action { TACTIC(ASK, system_problem, up, closed) } }\n"
         "  transition close { wait { up } action { TACTIC(EXEC, surface, aborted) } } }\n";
  auto c = client();
  auto v = c.Post("/api/verify", R"({"path": "tank/held.coral"})", "application/json");
  ASSERT_TRUE(v);
  ASSERT_EQ(200, v->status) << v->body;
  const json r = json::parse(v->body);
  EXPECT_FALSE(r["ok"].get<bool>());  // 5.2 s at worst, past 2 s
  const json* req = nullptr;
  for (const json& n : r["nets"]) {
    for (const json& p : n["properties"]) {
      if (p["key"] == "requirement") req = &p;
    }
  }
  ASSERT_NE(nullptr, req) << r.dump();
  EXPECT_EQ("fails", (*req)["status"]);
  ASSERT_TRUE(req->contains("counterexample")) << req->dump();
  const json& cx = (*req)["counterexample"];
  EXPECT_TRUE(cx.value("timed", false));
  std::set<std::string> instances;
  for (const json& st : cx["steps"]) {
    if (st.contains("instance")) instances.insert(st["instance"].get<std::string>());
  }
  EXPECT_EQ(std::set<std::string>({"held", "held/hold#1"}), instances) << cx.dump();
  EXPECT_EQ("fire", cx["steps"].back()["kind"]);
  EXPECT_EQ("close", cx["steps"].back()["transition"]);
  EXPECT_NEAR(5.2, cx["steps"].back()["t_s"].get<double>(), 1e-9);
}

TEST_F(StudioServerTest, AMissionWhoseDataFileIsOutsideIsNotRun) {
  std::ofstream(base_ / "outside.toml") << "secret = 1\n";
  fs::create_symlink("../../outside.toml", base_ / "root/tank/linked.toml");
  auto c = client();
  for (const char* data : {"../../outside.toml", "/etc/passwd", "linked.toml"}) {
    std::ofstream(base_ / "root/tank/data.coral")
        << "mission m { data \"" << data << "\"; place s = 1; exit e;\ntransition t { wait { s } signal { e } } }\n";
    auto r = c.Post("/api/run", R"({"path": "tank/data.coral"})", "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(403, r->status) << data << ": " << r->body;
    EXPECT_NE(std::string::npos, r->body.find("data file is outside")) << r->body;
  }
  EXPECT_TRUE(runs_.empty());
}

TEST_F(StudioServerTest, LayoutsAndLogsAreReadOnlyInsideTheFolder) {
  std::ofstream(base_ / "outside.json") << R"({"tank": {"secret": {"x": 1, "y": 2}}})";
  std::ofstream(base_ / "outside.jsonl") << "{\"event\": \"secret\"}\n";
  fs::create_symlink("../../outside.json", base_ / "root/tank/tank.coral.layout.json");
  fs::create_symlink("../outside.jsonl", base_ / "root/run.jsonl");
  auto c = client();
  auto m = c.Get("/api/mission?path=tank/tank.coral");
  ASSERT_TRUE(m);
  EXPECT_TRUE(json::parse(m->body)["layout"].is_null());
  auto replay = c.Get("/api/replay?path=run.jsonl");
  ASSERT_TRUE(replay);
  EXPECT_EQ(403, replay->status);
  EXPECT_EQ(std::string::npos, replay->body.find("secret"));
}

// Issue 17: a scenario of ../../../../etc/passwd leaked that file's parse error.
TEST_F(StudioServerTest, AScenarioIsANameFromTheMissionsFolder) {
  fs::create_directories(base_ / "outside");
  std::ofstream(base_ / "outside/evil.toml") << "seed = 1\n";
  fs::create_symlink("../../../outside/evil.toml", base_ / "root/tank/scenarios/evil.toml");
  auto c = client();
  for (const char* bad : {"../../../../etc/passwd", "/etc/passwd", "scenarios/leak_phase2", "leak_phase2.toml", "evil",
                          "none_such", "a b"}) {
    json body = {{"path", "tank/tank.coral"}, {"scenario", bad}};
    auto r = c.Post("/api/run", body.dump(), "application/json");
    ASSERT_TRUE(r) << bad;
    EXPECT_EQ(400, r->status) << bad << ": " << r->body;
    EXPECT_EQ(std::string::npos, r->body.find("root:")) << bad;
    EXPECT_TRUE(json::parse(r->body).contains("error")) << r->body;
  }
  EXPECT_TRUE(runs_.empty());
  auto m = json::parse(c.Get("/api/mission?path=tank/tank.coral")->body);
  EXPECT_EQ(m["scenarios"].end(), std::find(m["scenarios"].begin(), m["scenarios"].end(), "evil")) << m["scenarios"];
  // A name from the folder runs with its file; nominal, or none, also runs
  // where the mission has no scenarios/ at all.
  auto ok = c.Post("/api/run", R"({"path": "tank/tank.coral", "scenario": "leak_phase2"})", "application/json");
  ASSERT_TRUE(ok);
  EXPECT_EQ(202, ok->status) << ok->body;
  ASSERT_EQ(1u, runs_.size());
  EXPECT_EQ(fs::canonical(base_ / "root/tank/scenarios/leak_phase2.toml"), runs_[0].scenario_file);
  fs::create_directories(base_ / "root/bare");
  fs::copy(base_ / "root/tank", base_ / "root/bare", fs::copy_options::recursive);
  fs::remove_all(base_ / "root/bare/scenarios");
  for (const char* body : {R"({"path": "bare/tank.coral", "scenario": "nominal"})", R"({"path": "bare/tank.coral"})"}) {
    auto r = c.Post("/api/run", body, "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(202, r->status) << r->body;
    EXPECT_TRUE(runs_.back().scenario_file.empty());
  }
}

// Issue 17: two tabs on one mission; the second save silently dropped the
// first tab's change.
TEST_F(StudioServerTest, ASaveWithAStaleETagIsRefused) {
  auto c = client();
  const std::string tag = etag_of("tank/initialize.coral");
  ASSERT_FALSE(tag.empty());
  auto model = json::parse(c.Get("/api/mission?path=tank/initialize.coral")->body);
  EXPECT_EQ(tag, model["etag"]);
  // Tab one saves: a new tag.
  auto first = c.Put("/api/file?path=tank/initialize.coral", {{"If-Match", tag}}, "// tab one\n", "text/plain");
  ASSERT_TRUE(first);
  ASSERT_EQ(200, first->status) << first->body;
  const std::string next = first->get_header_value("ETag");
  EXPECT_NE(tag, next);
  EXPECT_EQ(next, json::parse(first->body)["etag"]);
  EXPECT_EQ(next, etag_of("tank/initialize.coral"));
  // Tab two, read before: refused, and tab one's change stays.
  auto second = c.Put("/api/file?path=tank/initialize.coral", {{"If-Match", tag}}, "// tab two\n", "text/plain");
  ASSERT_TRUE(second);
  EXPECT_EQ(412, second->status);
  EXPECT_NE(std::string::npos, json::parse(second->body)["error"].get<std::string>().find("changed since it was read"));
  EXPECT_EQ("// tab one\n", slurp(base_ / "root/tank/initialize.coral"));
  // A change on disk is a change too.
  std::ofstream(base_ / "root/tank/initialize.coral") << "// an editor\n";
  auto third = c.Put("/api/file?path=tank/initialize.coral", {{"If-Match", next}}, "// tab one again\n", "text/plain");
  ASSERT_TRUE(third);
  EXPECT_EQ(412, third->status);
  // Saving over an existing file without If-Match: 428; a new file needs none.
  auto blind = c.Put("/api/file?path=tank/initialize.coral", "x", "text/plain");
  ASSERT_TRUE(blind);
  EXPECT_EQ(428, blind->status);
  EXPECT_EQ("// an editor\n", slurp(base_ / "root/tank/initialize.coral"));
  // The layout has its own version, the same way.
  auto l1 = c.Put("/api/layout?path=tank/initialize.coral", R"({"a": {}})", "application/json");
  ASSERT_TRUE(l1);
  ASSERT_EQ(200, l1->status) << l1->body;
  model = json::parse(c.Get("/api/mission?path=tank/initialize.coral")->body);
  EXPECT_EQ(l1->get_header_value("ETag"), model["layout_etag"]);
  auto l2 =
      c.Put("/api/layout?path=tank/initialize.coral", {{"If-Match", "\"stale\""}}, R"({"b": {}})", "application/json");
  ASSERT_TRUE(l2);
  EXPECT_EQ(412, l2->status);
  auto l3 = c.Put("/api/layout?path=tank/initialize.coral", {{"If-Match", model["layout_etag"].get<std::string>()}},
                  R"({"b": {}})", "application/json");
  ASSERT_TRUE(l3);
  EXPECT_EQ(200, l3->status) << l3->body;
}

}  // namespace
}  // namespace strata::studio
