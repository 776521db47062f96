// The studio server's API for issue 17's later points, over loopback:
// changes on disk told to pages, deletes that leave no use behind, PROLOG
// missions, scenarios, the run list, Abort and Stop, errors and methods,
// and page assets compressed once at build time.
#include <sys/stat.h>

#include <cstdlib>
#include <future>
#include <set>

#include "studio/assets.h"
#include "studio/mission_model.h"
#include "studio/server_test_support.h"

namespace strata::studio {
namespace {

// Reads a stream until an event named `name` comes (or `bound` passes);
// returns its data, or null.
json next_event(EventHub::Subscription& sub, const std::string& name, std::chrono::seconds bound = 10s) {
  std::string text;
  for (auto end = std::chrono::steady_clock::now() + bound; std::chrono::steady_clock::now() < end;) {
    auto chunk = sub.next(100ms);
    if (!chunk) break;
    text += *chunk;
    const auto at = text.find("event: " + name + "\ndata: ");
    if (at == std::string::npos) continue;
    const auto data = at + name.size() + 14;
    return json::parse(text.substr(data, text.find('\n', data) - data));
  }
  return nullptr;
}

void write_file(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

TEST_F(StudioServerTest, AFileAPageShowsThatChangesOnDiskIsToldToPages) {
  auto sub = hub_.subscribe();
  auto c = client();
  ASSERT_EQ(200, c.Get("/api/mission?path=tank/tank.coral")->status);
  // An import changed by another program.
  const std::string changed = slurp(base_ / "root/tank/initialize.coral") + "\n// changed elsewhere\n";
  write_file(base_ / "root/tank/initialize.coral", changed);
  json e = next_event(*sub, "file_changed");
  ASSERT_TRUE(e.is_object()) << "no file_changed";
  EXPECT_EQ("tank/initialize.coral", e["path"]);
  EXPECT_EQ(studio::etag_of(changed), e["etag"]);

  // The same bytes written again are no news; the next event is the next
  // real change (the layout appearing).
  write_file(base_ / "root/tank/initialize.coral", changed);
  write_file(base_ / "root/tank/tank.coral.layout.json", "{}\n");
  e = next_event(*sub, "file_changed");
  ASSERT_TRUE(e.is_object());
  EXPECT_EQ("tank/tank.coral.layout.json", e["path"]);

  // A save from another tab is told too (the saving tab knows the etag it got).
  const std::string text = slurp(base_ / "root/tank/tank.coral") + "// saved by tab 2\n";
  auto put = c.Put("/api/file?path=tank/tank.coral", {{"If-Match", etag_of("tank/tank.coral")}}, text, "text/plain");
  ASSERT_EQ(200, put->status) << put->body;
  e = next_event(*sub, "file_changed");
  ASSERT_TRUE(e.is_object());
  EXPECT_EQ("tank/tank.coral", e["path"]);
  EXPECT_EQ(json::parse(put->body)["etag"], e["etag"]);

  // Gone: etag null.
  fs::remove(base_ / "root/tank/tank.coral.layout.json");
  e = next_event(*sub, "file_changed");
  ASSERT_TRUE(e.is_object());
  EXPECT_EQ("tank/tank.coral.layout.json", e["path"]);
  EXPECT_TRUE(e["etag"].is_null());
}

// A file swapped for a link out is told as gone, and what it points to is
// never read for the page.
TEST_F(StudioServerTest, AWatchedFileSwappedForALinkOutIsToldAsUnreadable) {
  auto sub = hub_.subscribe();
  auto c = client();
  ASSERT_EQ(200, c.Get("/api/mission?path=tank/tank.coral")->status);
  fs::remove(base_ / "root/tank/initialize.coral");
  fs::create_symlink(base_ / "secret.coral", base_ / "root/tank/initialize.coral");
  json e = next_event(*sub, "file_changed");
  ASSERT_TRUE(e.is_object());
  EXPECT_EQ("tank/initialize.coral", e["path"]);
  EXPECT_TRUE(e["etag"].is_null()) << e.dump();
}

json edit(httplib::Client& c, const std::string& text, const json& op, int& status) {
  auto r =
      c.Post("/api/edit", json{{"path", "tank/tank.coral"}, {"text", text}, {"op", op}}.dump(), "application/json");
  status = r ? r->status : 0;
  return r ? json::parse(r->body, nullptr, false) : json();
}

// Issue 17: deleting a place left its uses in PHASE(...) (docs/studio.md
// said they went too): the text no longer compiled.
TEST_F(StudioServerTest, DeletingAPlaceLeftItsUsesInPhaseOutcomes) {
  auto c = client();
  const std::string tank = slurp(base_ / "root/tank/tank.coral");
  int status = 0;
  json r = edit(c, tank, {{"op", "delete_place"}, {"net", "tank"}, {"name", "aborted"}}, status);
  EXPECT_EQ(400, status) << r.dump();
  EXPECT_NE(std::string::npos, r.value("error", "").find("PHASE(initialize, initialized, aborted)")) << r.dump();
  EXPECT_NE(std::string::npos, r.value("error", "").find("'phase1'")) << r.dump();
  // An exit: every PHASE of the net counts them.
  r = edit(c, tank, {{"op", "delete_place"}, {"net", "tank"}, {"name", "closed"}}, status);
  EXPECT_EQ(400, status) << r.dump();
  EXPECT_NE(std::string::npos, r.value("error", "").find("exit")) << r.dump();
  // A TACTIC's answer.
  r = edit(c, tank, {{"op", "delete_place"}, {"net", "tank"}, {"name", "closed_after_abort"}}, status);
  EXPECT_EQ(400, status) << r.dump();
}

TEST_F(StudioServerTest, DeletingAPlaceOrTransitionRemovesEveryUse) {
  auto c = client();
  std::string tank = slurp(base_ / "root/tank/tank.coral");
  // A place used only by arcs: it goes, and its arcs with it.
  const std::string with_spare =
      tank.substr(0, tank.rfind('}')) +
      "  place spare;\n  transition use_spare { wait { spare, finished } signal { spare } }\n}\n";
  int status = 0;
  json r = edit(c, with_spare, {{"op", "delete_place"}, {"net", "tank"}, {"name", "spare"}}, status);
  ASSERT_EQ(200, status) << r.dump();
  EXPECT_EQ(std::string::npos, r["text"].get<std::string>().find("spare,")) << r["text"];
  for (const auto& d : r["diagnostics"]) EXPECT_NE("error", d["severity"]) << d.dump();
  // A transition: nothing else names it.
  r = edit(c, tank, {{"op", "delete_transition"}, {"net", "tank"}, {"name", "abort_mission"}}, status);
  ASSERT_EQ(200, status) << r.dump();
  EXPECT_EQ(std::string::npos, r["text"].get<std::string>().find("abort_mission"));
  for (const auto& d : r["diagnostics"]) EXPECT_NE("error", d["severity"]) << d.dump();
  EXPECT_EQ(5u, r["nets"].size());
}

// When the text does not compile for another reason, the refusal comes from
// the result: an error naming the deleted place that was not there before.
TEST_F(StudioServerTest, ADeleteThatWouldLeaveAUseIsRefusedAlsoInTextWithOtherErrors) {
  auto c = client();
  std::string tank = slurp(base_ / "root/tank/tank.coral");
  const auto at = tank.find("shutdown_network, closed)");
  ASSERT_NE(std::string::npos, at);
  tank.replace(at, std::string("shutdown_network").size(), "shutdown_netwrk");  // an unknown primitive
  int status = 0;
  json r = edit(c, tank, {{"op", "delete_place"}, {"net", "tank"}, {"name", "aborted"}}, status);
  EXPECT_EQ(400, status) << r.dump();
  EXPECT_NE(std::string::npos, r.value("error", "").find("'aborted'")) << r.dump();
}

TEST_F(StudioServerTest, PrologMissionsAreListedShownReadOnlyAndRun) {
  auto c = client();
  json files = json::parse(c.Get("/api/files")->body);
  EXPECT_NE(files["missions"].end(), std::find(files["missions"].begin(), files["missions"].end(),
                                               json({{"path", "tank/tank.pl"}, {"kind", "prolog"}})))
      << files["missions"];
  EXPECT_NE(files["missions"].end(), std::find(files["missions"].begin(), files["missions"].end(),
                                               json({{"path", "tank/tank.coral"}, {"kind", "coral"}})));
  EXPECT_EQ(files["files"].end(), std::find(files["files"].begin(), files["files"].end(), "tank/tank.pl"));

  auto m = c.Get("/api/mission?path=tank/tank.pl");
  ASSERT_EQ(200, m->status) << m->body;
  json model = json::parse(m->body);
  EXPECT_EQ("prolog", model["kind"]);
  EXPECT_TRUE(model["read_only"].get<bool>());
  EXPECT_EQ(slurp(base_ / "root/tank/tank.pl"), model["text"]);
  EXPECT_TRUE(model["nets"].empty());
  EXPECT_EQ("done", model["check"]);
  EXPECT_TRUE(model["diagnostics"].empty()) << model["diagnostics"].dump();
  EXPECT_EQ(m->get_header_value("ETag"), model["etag"]);

  write_file(base_ / "root/tank/bad.pl", "mission :- exec_sleep(1, X), X = .\n");
  model = json::parse(c.Get("/api/mission?path=tank/bad.pl")->body);
  ASSERT_FALSE(model["diagnostics"].empty()) << model.dump();
  EXPECT_EQ("error", model["diagnostics"][0]["severity"]);
  EXPECT_EQ(1, model["diagnostics"][0].value("line", 0)) << model["diagnostics"].dump();
  EXPECT_EQ("tank/bad.pl", model["diagnostics"][0].value("file", "")) << "named inside the folder";
  EXPECT_EQ("PrologLoadError", model["diagnostics"][0].value("kind", "")) << model["diagnostics"].dump();

  const std::string before = slurp(base_ / "root/tank/tank.pl");
  auto put = c.Put("/api/file?path=tank/tank.pl", {{"If-Match", "*"}}, "mission.\n", "text/plain");
  EXPECT_EQ(403, put->status);
  EXPECT_NE(std::string::npos, json::parse(put->body).value("error", "").find("read-only"));
  EXPECT_EQ(before, slurp(base_ / "root/tank/tank.pl"));

  auto run = c.Post("/api/run", R"({"path": "tank/tank.pl"})", "application/json");
  ASSERT_EQ(202, run->status) << run->body;
  EXPECT_EQ(".pl", runs_.back().mission.extension());
  auto other = c.Post("/api/run", R"({"path": "tank/setpoints.toml"})", "application/json");
  EXPECT_EQ(400, other->status);
}

// Issue 17: the page always sent "nominal", which a mission without
// scenarios/nominal.toml did not list.
TEST_F(StudioServerTest, ScenariosAlwaysListNominal) {
  auto c = client();
  json m = json::parse(c.Get("/api/mission?path=tank/tank.coral")->body);
  EXPECT_NE(m["scenarios"].end(), std::find(m["scenarios"].begin(), m["scenarios"].end(), "leak_phase2"));
  EXPECT_EQ(1, std::count(m["scenarios"].begin(), m["scenarios"].end(), "nominal"));
  fs::remove_all(base_ / "root/tank/scenarios");
  m = json::parse(c.Get("/api/mission?path=tank/tank.coral")->body);
  EXPECT_EQ(json::array({"nominal"}), m["scenarios"]);
}

TEST_F(StudioServerTest, RunsAreListedPerMissionNewestFirst) {
  fs::create_directories(base_ / "root/tank/runs");
  fs::create_directories(base_ / "root/other/runs");
  for (const char* name : {"tank/runs/20261125T101010Z-tank.jsonl", "tank/runs/20261125T111111Z-tank.coral-2.jsonl",
                           "tank/runs/20261125T141414Z-tank.pl.jsonl", "tank/runs/notes.jsonl",
                           "other/runs/20261125T121212Z-other.coral.jsonl", "tank/run.jsonl"}) {
    write_file(base_ / "root" / name, "{\"event\":\"run\"}\n");
  }
  std::ofstream(base_ / "outside.jsonl") << "{}\n";
  fs::create_symlink("../../../outside.jsonl", base_ / "root/tank/runs/20261125T131313Z-tank.jsonl");
  auto c = client();
  json r = json::parse(c.Get("/api/runs?mission=tank/tank.coral")->body);
  ASSERT_EQ(2u, r["runs"].size()) << r.dump();
  EXPECT_EQ("tank/runs/20261125T111111Z-tank.coral-2.jsonl", r["runs"][0]["path"]);
  EXPECT_EQ("2026-11-25T11:11:11Z", r["runs"][0]["started"]);
  EXPECT_EQ("tank.coral", r["runs"][0]["mission_file"]);
  EXPECT_EQ("tank/runs/20261125T101010Z-tank.jsonl", r["runs"][1]["path"]) << "a log named by the stem only";
  // Regression: tank.pl's runs were listed as tank.coral's (matched by stem).
  r = json::parse(c.Get("/api/runs?mission=tank/tank.pl")->body);
  ASSERT_EQ(2u, r["runs"].size()) << r.dump();
  EXPECT_EQ("tank/runs/20261125T141414Z-tank.pl.jsonl", r["runs"][0]["path"]);
  EXPECT_EQ("tank/runs/20261125T101010Z-tank.jsonl", r["runs"][1]["path"]);
  r = json::parse(c.Get("/api/runs")->body);
  EXPECT_EQ(4u, r["runs"].size()) << r.dump();
  EXPECT_EQ(403, c.Get("/api/runs?mission=../secret.coral")->status);
}

TEST_F(StudioServerTest, AReplayNamesItsMissionRelativeToTheFolder) {
  const std::string log =
      json{{"event", "run"}, {"mission", (fs::canonical(base_ / "root") / "tank/tank.coral").string()}}.dump() + "\n" +
      json{{"event", "mission_end"}, {"outcome", "aborted"}, {"sim_time", 3.0}}.dump() + "\n";
  fs::create_directories(base_ / "root/tank/runs");
  write_file(base_ / "root/tank/runs/20261125T101010Z-tank.jsonl", log);
  auto r = client().Get("/api/replay?path=tank/runs/20261125T101010Z-tank.jsonl");
  ASSERT_EQ(200, r->status) << r->body;
  json j = json::parse(r->body);
  EXPECT_EQ("tank/tank.coral", j["mission"]);
  EXPECT_EQ("aborted", j["events"].back()["data"]["outcome"]);
}

// Issue 20: the map panel of a replay draws the track from the log's
// estimated position; a tank log's telemetry has none, and gets none.
TEST_F(StudioServerTest, AReplaysTelemetryCarriesThePositionWhereTheLogHasOne) {
  const std::string log =
      json{{"event", "run"}, {"mission", "survey.coral"}}.dump() + "\n" +
      json{{"event", "telemetry"}, {"sim_time", 1.0}, {"depth_m", 0.5}, {"x_m", 10.25}, {"y_m", -4.5}}.dump() + "\n" +
      json{{"event", "telemetry"}, {"sim_time", 2.0}, {"depth_m", 0.7}, {"setpoint_m", 1.0}}.dump() + "\n";
  fs::create_directories(base_ / "root/survey/runs");
  write_file(base_ / "root/survey/runs/20261125T101010Z-survey.jsonl", log);
  auto r = client().Get("/api/replay?path=survey/runs/20261125T101010Z-survey.jsonl");
  ASSERT_EQ(200, r->status) << r->body;
  json j = json::parse(r->body);
  ASSERT_EQ(2u, j["events"].size()) << j.dump();
  const json& open = j["events"][0]["data"];
  EXPECT_EQ(10.25, open["x"]);
  EXPECT_EQ(-4.5, open["y"]);
  EXPECT_EQ(1.0, open["t"]);
  EXPECT_FALSE(j["events"][1]["data"].contains("x")) << j.dump();
}

TEST_F(StudioServerTest, AReplayKeepsTheScriptedAnswersOfARunWithAnswers) {
  // Regression: the replay dropped a --answers run's scripted_answer,
  // scripted_phase and answers_diverged records, so the studio showed the
  // witness's path without saying which answers were the script's.
  const std::string log =
      json{{"event", "run"}, {"mission", "tank/tank.coral"}}.dump() + "\n" +
      json{{"event", "scripted_answer"},
           {"answer_index", 0},
           {"step", 3},
           {"net", "dive_from_surface"},
           {"transition", "check_filter"},
           {"action", "ask"},
           {"primitive", "filter_on"},
           {"vehicle", 0},
           {"answer", 1},
           {"sim_time", 1.5}}
          .dump() +
      "\n" +
      json{{"event", "scripted_phase"},
           {"answer_index", 1},
           {"step", 4},
           {"net", "tank"},
           {"transition", "dive"},
           {"phase", "dive_from_surface"},
           {"exit", "abort"},
           {"sim_time", 2.0}}
          .dump() +
      "\n" +
      json{{"event", "answers_diverged"}, {"reason", "exec x was called"}, {"used", 2}, {"sim_time", 2.5}}.dump() +
      "\n" + json{{"event", "mission_end"}, {"outcome", "failed"}, {"sim_time", 3.0}}.dump() + "\n";
  fs::create_directories(base_ / "root/tank/runs");
  write_file(base_ / "root/tank/runs/20261125T121212Z-tank.coral.jsonl", log);
  auto r = client().Get("/api/replay?path=tank/runs/20261125T121212Z-tank.coral.jsonl");
  ASSERT_EQ(200, r->status) << r->body;
  const json events = json::parse(r->body)["events"];
  ASSERT_EQ(4u, events.size()) << events.dump();
  EXPECT_EQ("scripted_answer", events[0]["event"]);
  EXPECT_EQ((json{{"answer_index", 0},
                  {"step", 3},
                  {"net", "dive_from_surface"},
                  {"transition", "check_filter"},
                  {"action", "ask"},
                  {"primitive", "filter_on"},
                  {"vehicle", 0},
                  {"answer", 1},
                  {"t", 1.5}}),
            events[0]["data"]);
  EXPECT_EQ("scripted_phase", events[1]["event"]);
  EXPECT_EQ("abort", events[1]["data"]["exit"]);
  EXPECT_EQ("answers_diverged", events[2]["event"]);
  EXPECT_EQ("exec x was called", events[2]["data"]["reason"]);
}

TEST_F(StudioServerTest, AbortAndStopGoToTheRunner) {
  auto c = client();
  EXPECT_EQ(200, c.Post("/api/run/abort", "", "application/json")->status);
  EXPECT_EQ(1, launcher_.aborts);
  EXPECT_EQ(0, launcher_.stops);
  EXPECT_EQ(200, c.Post("/api/run/stop", "", "application/json")->status);
  EXPECT_EQ(1, launcher_.stops);
}

TEST_F(StudioServerTest, ErrorsAreJsonWithTheRightStatusAndMethodsAreChecked) {
  auto c = client();
  auto check = [](const httplib::Result& r, int status, const char* what) {
    ASSERT_TRUE(r) << what;
    EXPECT_EQ(status, r->status) << what << ": " << r->body;
    EXPECT_EQ("application/json", r->get_header_value("Content-Type")) << what;
    EXPECT_TRUE(json::parse(r->body, nullptr, false).contains("error")) << what << ": " << r->body;
  };
  auto get_run = c.Get("/api/run");
  check(get_run, 405, "GET /api/run");
  EXPECT_EQ("POST", get_run->get_header_value("Allow"));
  auto post_files = c.Post("/api/files", "{}", "application/json");
  check(post_files, 405, "POST /api/files");
  EXPECT_EQ("GET, HEAD", post_files->get_header_value("Allow"));
  check(c.Put("/api/mission?path=tank/tank.coral", "x", "text/plain"), 405, "PUT /api/mission");
  check(c.Delete("/api/file?path=tank/tank.coral"), 405, "DELETE /api/file");
  check(c.Get("/api/nothing"), 404, "GET /api/nothing");
  check(c.Post("/api/nothing", "{}", "application/json"), 404, "POST /api/nothing");
  check(c.Get("/no-such-asset.js"), 404, "GET /no-such-asset.js");
  check(c.Get("/api/mission?path=tank/none.coral"), 404, "GET a mission not there");
  check(c.Get("/api/replay?path=tank/none.jsonl"), 404, "replay a log not there");
  check(c.Post("/api/check", "not json", "application/json"), 400, "a body that is not JSON");
  check(c.Post("/api/edit", R"({"path": "tank/tank.coral", "text": "", "op": {"op": "fly"}})", "application/json"), 400,
        "an unknown op");
  check(c.Post("/api/run", R"({"path": "tank/tank.coral", "speed": "fast"})", "application/json"), 400, "a bad speed");
}

// Check, edit and verify take their mission through one lambda
// (mission_body): every body it or the route refuses is a JSON error with a
// 4xx status, never a 500, and nothing outside the folder is read.
TEST_F(StudioServerTest, AMissionBodyThatIsWrongIsA4xxJsonErrorOnEveryRoute) {
  auto c = client();
  fs::create_symlink(base_ / "secret.coral", base_ / "root/out.coral");
  fs::create_symlink("loop.coral", base_ / "root/loop.coral");
  fs::create_symlink(base_, base_ / "root/up");
  const std::string text = slurp(base_ / "root/tank/tank.coral");
  const json op = {{"op", "rename_place"}, {"name", "nowhere"}, {"to", "elsewhere"}};
  const std::vector<json> bodies = {
      json::object(),
      {{"path", 3}},
      {{"path", json::array({"tank/tank.coral"})}},
      {{"path", nullptr}},
      {{"path", json::object()}},
      {{"path", ""}},
      {{"path", "../secret.coral"}},
      {{"path", "tank/../../secret.coral"}},
      {{"path", (base_ / "secret.coral").string()}},
      {{"path", "/etc/passwd"}},
      {{"path", "out.coral"}},
      {{"path", "up/secret.coral"}},
      {{"path", "loop.coral"}},
      {{"path", std::string("tank/tank.coral\0x", 17)}},
      {{"path", "tank/tank.coral"}, {"text", 3}},
      {{"path", "tank/tank.coral"}, {"text", text}, {"base", json::array()}},
  };
  for (const char* route : {"/api/check", "/api/edit", "/api/verify"}) {
    for (json body : bodies) {
      if (std::string(route) == "/api/edit" && !body.contains("op")) body["op"] = op;
      auto r = c.Post(route, body.dump(), "application/json");
      ASSERT_TRUE(r) << route << " " << body.dump();
      const json answer = json::parse(r->body, nullptr, false);
      if (r->status == 200) continue;  // a mission body it may take (the text's own errors in the model)
      EXPECT_TRUE(r->status >= 400 && r->status < 500)
          << route << " " << body.dump() << ": " << r->status << " " << r->body;
      EXPECT_TRUE(answer.is_object() && answer.contains("error")) << route << " " << body.dump() << ": " << r->body;
      EXPECT_EQ(std::string::npos, r->body.find("net secret")) << route << " " << body.dump();
    }
  }
  // Those refused by the path alone.
  for (const char* route : {"/api/check", "/api/edit", "/api/verify"}) {
    for (const json& path :
         {json(3), json(nullptr), json::array(), json(""), json("../secret.coral"),
          json((base_ / "secret.coral").string()), json("out.coral"), json("up/secret.coral"), json("loop.coral")}) {
      json body = {{"path", path}, {"text", text}};
      if (std::string(route) == "/api/edit") body["op"] = op;
      auto r = c.Post(route, body.dump(), "application/json");
      ASSERT_TRUE(r);
      EXPECT_TRUE(r->status >= 400 && r->status < 500) << route << " " << body["path"].dump() << ": " << r->status;
    }
  }
}

// A name the system refuses (longer than a file name may be) inside the
// folder: the mission's places cannot be made canonical.
TEST_F(StudioServerTest, AMissionPathTheSystemCannotLookUpIsA4xxNotA500) {
  auto c = client();
  const std::string text = slurp(base_ / "root/tank/tank.coral");
  const std::string name = std::string(300, 'n') + ".coral";
  const json op = {{"op", "rename_place"}, {"name", "nowhere"}, {"to", "elsewhere"}};
  for (const char* route : {"/api/check", "/api/edit", "/api/verify"}) {
    auto r = c.Post(route, json{{"path", name}, {"text", text}, {"op", op}}.dump(), "application/json");
    ASSERT_TRUE(r);
    EXPECT_LT(r->status, 500) << route << ": " << r->body;
    EXPECT_TRUE(json::parse(r->body, nullptr, false).is_object()) << route << ": " << r->body;
  }
}

// Issue 17: the 604 KB page was brotli-compressed on every request (0.8 s of
// each page load). The bytes sent are the ones compressed at build time.
TEST_F(StudioServerTest, ThePageWasCompressedOnEveryRequest) {
  auto asset = embedded_asset("index.html");
  ASSERT_TRUE(asset);
  ASSERT_FALSE(asset->brotli.empty());
  ASSERT_FALSE(asset->gzip.empty());
  httplib::Client c("127.0.0.1", port_);
  c.set_decompress(false);
  auto br = c.Get("/", {{"Accept-Encoding", "gzip, deflate, br"}});
  ASSERT_TRUE(br);
  EXPECT_EQ("br", br->get_header_value("Content-Encoding"));
  EXPECT_EQ("Accept-Encoding", br->get_header_value("Vary"));
  EXPECT_EQ(asset->brotli, br->body);
  auto gz = c.Get("/", {{"Accept-Encoding", "br;q=0, gzip"}});
  EXPECT_EQ("gzip", gz->get_header_value("Content-Encoding"));
  EXPECT_EQ(asset->gzip, gz->body);
  auto plain = c.Get("/", {{"Accept-Encoding", "identity"}});
  EXPECT_FALSE(plain->has_header("Content-Encoding"));
  EXPECT_EQ(asset->data, plain->body);
  // Decompressed by a client that asks for it, the same page.
  httplib::Client d("127.0.0.1", port_);
  auto again = d.Get("/", {{"Accept-Encoding", "br"}});
  EXPECT_EQ(asset->data, again->body);
  // Nor is JSON compressed per request.
  auto files = c.Get("/api/files", {{"Accept-Encoding", "gzip, deflate, br"}});
  EXPECT_FALSE(files->has_header("Content-Encoding"));
  EXPECT_TRUE(json::parse(files->body, nullptr, false).is_object());
}

}  // namespace
}  // namespace strata::studio
