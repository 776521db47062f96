// Edits answered with a patch of the model the page holds: what the patch
// says for the usual edits, and when the server answers the whole model.
#include "studio/model_patch.h"

#include <map>

#include "studio/server_test_support.h"

namespace strata::studio {
namespace {

json place(const std::string& name, int line) {
  return {{"name", name}, {"initial", 0}, {"exit", false}, {"line", line}};
}
json transition(const std::string& name, int line, const std::string& in) {
  return {{"name", name},
          {"priority", 0},
          {"line", line},
          {"inputs", json::array({{{"place", in}, {"weight", 1}}})},
          {"outputs", json::array()},
          {"actions", json::array()}};
}
json model(const std::string& text, json places, json transitions) {
  return {{"path", "m.coral"},
          {"text", text},
          {"diagnostics", json::array()},
          {"layout", nullptr},
          {"rev", "x"},
          {"nets", json::array({{{"name", "m"},
                                 {"kind", "mission"},
                                 {"file", "m.coral"},
                                 {"editable", true},
                                 {"exits", json::array()},
                                 {"places", places},
                                 {"transitions", transitions}}})}};
}

TEST(ModelPatch, APlaceAddedIsOneInsertAndTheLinesBelowMoveByOne) {
  const json before =
      model("net m {\n  place a;\n  transition t { wait { a } }\n}\n", {place("a", 2)}, {transition("t", 3, "a")});
  const json after = model("net m {\n  place a;\n  place b;\n  transition t { wait { a } }\n}\n",
                           {place("a", 2), place("b", 3)}, {transition("t", 4, "a")});
  const json p = model_patch(before, after);
  EXPECT_EQ(json({{"at", 2}, {"remove", 0}, {"insert", {"  place b;"}}}), p["text"]) << p.dump();
  EXPECT_EQ(json({{"from", 3}, {"by", 1}}), p["shift"]);
  ASSERT_EQ(1u, p["nets"].size());
  const json& net = p["nets"][0];
  EXPECT_EQ(0, net["from"]);
  EXPECT_TRUE(net["shift"].get<bool>());
  EXPECT_EQ(json({{"at", 1}, {"remove", 0}, {"insert", {place("b", 3)}}}), net["places"]) << net.dump();
  EXPECT_FALSE(net.contains("transitions")) << "t only moved down a line: " << net.dump();
  EXPECT_FALSE(net.contains("fields"));
  EXPECT_TRUE(p["fields"].empty()) << p.dump();
  EXPECT_TRUE(p["drop"].empty());
}

TEST(ModelPatch, ChangedMembersAndNetsComeWholeAndGoneOnesAreNamed) {
  json before = model("a\n", json::array(), json::array());
  json after = before;
  after["diagnostics"] = json::array({{{"severity", "error"}, {"message", "x"}}});
  after.erase("layout");
  after["nets"].push_back({{"name", "n2"}, {"places", json::array()}});
  after["nets"][0]["exits"] = {"done"};
  after["rev"] = "y";
  const json p = model_patch(before, after);
  EXPECT_EQ(json({{"diagnostics", after["diagnostics"]}}), p["fields"]);
  EXPECT_EQ(json({"layout"}), p["drop"]);
  EXPECT_EQ(json({{"at", 2}, {"remove", 0}, {"insert", json::array()}}), p["text"]);
  ASSERT_EQ(2u, p["nets"].size());
  EXPECT_EQ(json({{"exits", {"done"}}}), p["nets"][0]["fields"]);
  EXPECT_EQ(after["nets"][1], p["nets"][1]["net"]);
}

TEST(ModelCache, KeepsTheLastFewModelsUnderRevisionsOfItsOwn) {
  ModelCache a, b;
  auto first = a.keep(json{{"n", 1}});
  const std::string rev = (*first)["rev"];
  EXPECT_EQ(first, a.find(rev));
  EXPECT_EQ(nullptr, b.find(rev));
  EXPECT_NE(rev, (*b.keep(json{{"n", 1}}))["rev"].get<std::string>()) << "another server's revision";
  for (std::size_t i = 0; i < ModelCache::kEntries; ++i) a.keep(json{{"n", i}});
  EXPECT_EQ(nullptr, a.find(rev));
}

json post_edit(httplib::Client& c, const json& body) {
  auto r = c.Post("/api/edit", body.dump(), "application/json");
  EXPECT_TRUE(r && r->status == 200) << (r ? r->body : "no answer");
  return r ? json::parse(r->body, nullptr, false) : json();
}

TEST_F(StudioServerTest, AnEditOfTheModelAPageHoldsIsAnsweredWithAPatch) {
  auto c = client();
  auto opened = c.Get("/api/mission?path=tank/tank.coral");
  ASSERT_TRUE(opened && opened->status == 200);
  const json m = json::parse(opened->body);
  ASSERT_TRUE(m["rev"].is_string()) << "every model answered has a revision";
  const json op = {{"op", "add_place"}, {"net", "tank"}, {"name", "extra"}};
  const json full = post_edit(c, {{"path", "tank/tank.coral"}, {"text", m["text"]}, {"op", op}});
  ASSERT_TRUE(full.contains("nets")) << "no base: the whole model";
  json a = post_edit(c, {{"path", "tank/tank.coral"}, {"text", m["text"]}, {"op", op}, {"base", m["rev"]}});
  ASSERT_TRUE(a.contains("patch")) << a.dump().substr(0, 300);
  EXPECT_EQ(m["rev"], a["base"]);
  EXPECT_NE(m["rev"], a["rev"]);
  // The tank mission's nets but the one edited are unchanged.
  std::size_t unchanged = 0;
  for (const auto& e : a["patch"]["nets"]) unchanged += e.size() == 2;  // {from, shift}
  EXPECT_EQ(full["nets"].size() - 1, unchanged) << a["patch"]["nets"].dump();
  // The patch's revision is a base in turn.
  json b = post_edit(c, {{"path", "tank/tank.coral"},
                         {"text", full["text"]},
                         {"op", {{"op", "add_place"}, {"net", "tank"}, {"name", "more"}}},
                         {"base", a["rev"]}});
  EXPECT_TRUE(b.contains("patch"));
  // m is now the oldest of the models kept, and still a base when the
  // edit's own model comes.
  static_assert(ModelCache::kEntries == 4, "m, full, a, b");
  json oldest = post_edit(c, {{"path", "tank/tank.coral"}, {"text", m["text"]}, {"op", op}, {"base", m["rev"]}});
  EXPECT_TRUE(oldest.contains("patch")) << "the base was dropped for the edit's own model";
  // A base that is not known, or of another text: the whole model.
  json d = post_edit(c, {{"path", "tank/tank.coral"}, {"text", m["text"]}, {"op", op}, {"base", "nope"}});
  EXPECT_TRUE(d.contains("nets") && !d.contains("patch"));
  d = post_edit(c, {{"path", "tank/tank.coral"}, {"text", m["text"]}, {"op", op}, {"base", a["rev"]}});
  EXPECT_TRUE(d.contains("nets") && !d.contains("patch")) << "base a is of another text";
}

// Issue 20: the model shows a phase's parameters and a PHASE call's
// arguments (in its label too), and an edit of the actions keeps them.
TEST_F(StudioServerTest, APhaseWithParametersShowsAndKeepsItsArguments) {
  auto c = client();
  const std::string text = R"(// The box of docs/language.md ("phase parameters"), for the export round trip:
// a parameterised phase is exported once, with its calls' arguments on the
// DOT labels.
// One net for a turn and a hold, run with different arguments: a box of
// four headings. deg and hold_s are numbers, the default type.
net turn_and_hold(deg, hold_s) {
  place start = 1, turned;
  exit done;

  transition turn { wait { start } action { TACTIC(EXEC, heading(deg), turned) } }
  transition hold { wait { turned } action { TACTIC(EXEC, sleep(hold_s), done) } }
}

// A parameter may be passed on to a nested PHASE.
net side(deg) {
  place start = 1;
  exit done;

  transition go { wait { start } action { PHASE(turn_and_hold(deg, 5), done) } }
}

mission box {
  place begin = 1, up, north, east, south, west;
  exit completed;

  transition start { wait { begin } action { TACTIC(OOD, start_network, up) } }
  transition one   { wait { up } action { PHASE(side(0), north) } }
  transition two   { wait { north } action { PHASE(side(90), east) } }
  transition three { wait { east }  action { PHASE(side(180), south) } }
  transition four  { wait { south } action { PHASE(turn_and_hold(270, 2.5), west) } }
  transition stop  { wait { west } action { TACTIC(OOD, shutdown_network, completed) } }
}
)";
  auto put = c.Put("/api/file?path=tank/box.coral", text, "text/plain");
  ASSERT_TRUE(put && put->status < 300) << (put ? put->body : "no answer");
  const json op = {
      {"op", "set_actions"},
      {"net", "box"},
      {"transition", "four"},
      {"actions", {{{"kind", "PHASE"}, {"target", "turn_and_hold"}, {"args", {"270", "3"}}, {"outcomes", {"west"}}}}}};
  const json m = post_edit(c, {{"path", "tank/box.coral"}, {"text", text}, {"op", op}});
  ASSERT_TRUE(m.contains("nets")) << m.dump().substr(0, 300);
  EXPECT_NE(std::string::npos, m["text"].get<std::string>().find("PHASE(turn_and_hold(270, 3), west)"))
      << m["text"].get<std::string>();
  EXPECT_TRUE(m["diagnostics"].empty()) << m["diagnostics"].dump();
  std::map<std::string, json> nets;
  for (const auto& n : m["nets"]) nets[n["name"]] = n;
  EXPECT_EQ(json::parse(R"([{"name": "deg", "type": "number"}, {"name": "hold_s", "type": "number"}])"),
            nets["turn_and_hold"]["params"]);
  EXPECT_EQ(json::array(), nets["box"]["params"]);
  std::map<std::string, json> actions;
  for (const auto& t : nets["box"]["transitions"]) actions[t["name"]] = t["actions"][0];
  EXPECT_EQ(json::parse(R"(["90"])"), actions["two"]["args"]);
  EXPECT_EQ("PHASE side(90)", actions["two"]["label"]);
  EXPECT_EQ(json::parse(R"(["270", "3"])"), actions["four"]["args"]);
}

// A REPORT of a string parameter: the model shows the parameter as the
// action's argument (its label too), and an edit of the transition's
// actions, which sends it back as the page got it, keeps it.
TEST_F(StudioServerTest, AReportOfAParameterShowsAndKeepsItsName) {
  auto c = client();
  const std::string text = R"(net say(string text) {
  place start = 1, said;
  exit done;
  transition t { wait { start } action { TACTIC(REPORT, text) } signal { said } }
  transition u { wait { said } action { TACTIC(EXEC, sleep(1), done) } }
}
mission m {
  place begin = 1;
  exit completed;
  transition one { wait { begin } action { PHASE(say("hello"), completed) } }
}
)";
  auto put = c.Put("/api/file?path=tank/say.coral", text, "text/plain");
  ASSERT_TRUE(put && put->status < 300) << (put ? put->body : "no answer");
  auto opened = c.Get("/api/mission?path=tank/say.coral");
  ASSERT_TRUE(opened && opened->status == 200);
  const json model = json::parse(opened->body);
  json report;
  for (const auto& n : model["nets"]) {
    if (n["name"] != "say") continue;
    for (const auto& t : n["transitions"]) {
      if (t["name"] == "t") report = t["actions"][0];
    }
  }
  ASSERT_TRUE(report.is_object()) << opened->body.substr(0, 300);
  EXPECT_EQ(json::parse(R"(["text"])"), report["args"]);
  EXPECT_EQ("REPORT text", report["label"]);
  const json op = {{"op", "set_actions"}, {"net", "say"}, {"transition", "t"}, {"actions", json::array({report})}};
  const json m = post_edit(c, {{"path", "tank/say.coral"}, {"text", text}, {"op", op}});
  ASSERT_TRUE(m.contains("nets")) << m.dump().substr(0, 300);
  EXPECT_NE(std::string::npos, m["text"].get<std::string>().find("TACTIC(REPORT, text)"))
      << m["text"].get<std::string>();
  EXPECT_TRUE(m["diagnostics"].empty()) << m["diagnostics"].dump();
}

TEST_F(StudioServerTest, AnEditWhoseBaseIsNotAStringIsRefusedWith400) {
  auto c = client();
  auto opened = c.Get("/api/mission?path=tank/tank.coral");
  ASSERT_TRUE(opened && opened->status == 200);
  const json m = json::parse(opened->body);
  const json op = {{"op", "add_place"}, {"net", "tank"}, {"name", "extra"}};
  for (const json& base : {json(42), json::array({m["rev"]}), json::object({{"rev", m["rev"]}}), json(nullptr)}) {
    const json body = {{"path", "tank/tank.coral"}, {"text", m["text"]}, {"op", op}, {"base", base}};
    auto r = c.Post("/api/edit", body.dump(), "application/json");
    ASSERT_TRUE(r) << base.dump();
    EXPECT_EQ(400, r->status) << base.dump() << ": " << r->body;
    const json answer = json::parse(r->body, nullptr, false);
    EXPECT_TRUE(answer.is_object() && answer.contains("error")) << r->body;
  }
  // The server still answers an edit after them.
  EXPECT_TRUE(post_edit(c, {{"path", "tank/tank.coral"}, {"text", m["text"]}, {"op", op}}).contains("nets"));
}

}  // namespace
}  // namespace strata::studio
