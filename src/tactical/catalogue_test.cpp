#include "tactical/catalogue.h"

#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tactical/catalogue_print.h"
#include "core/test_fifo.h"

namespace strata::tactical {
namespace {

const std::string kSourceDir = STRATA_SOURCE_DIR;

std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string parse_error(const std::string& text) {
  auto c = Catalogue::parse(text, "cat.toml");
  EXPECT_FALSE(c.ok());
  return c.ok() ? "" : c.error().message;
}

TEST(Catalogue, BuiltinParsesAndHasEveryFigure10Primitive) {
  const Catalogue& c = Catalogue::builtin();
  EXPECT_EQ("<builtin>/config/primitives.toml", c.source());
  const std::vector<std::pair<std::string, Kind>> figure10 = {
      {"next_setpt_data", Kind::Exec}, {"start_depth_filter", Kind::Exec},
      {"submerge", Kind::Exec},        {"start_timer", Kind::Exec},
      {"sleep", Kind::Exec},           {"surface", Kind::Exec},
      {"depth_filter_off", Kind::Ask}, {"depth_reached", Kind::Ask},
      {"time_out", Kind::Ask},         {"system_problem", Kind::Ask},
      {"surface_reached", Kind::Ask},  {"start_network", Kind::Ood},
      {"shutdown_network", Kind::Ood}, {"report", Kind::Report}};
  for (const auto& [name, kind] : figure10) {
    const Primitive* p = c.find(name);
    ASSERT_TRUE(p) << name;
    EXPECT_EQ(kind, p->kind) << name;
    EXPECT_FALSE(p->doc.empty()) << name;
    if (kind != Kind::Report) {
      EXPECT_GT(p->timeout_s, 0) << name;
    }
  }
  // Figure 10's and the five of the heading and the sonar (issue 8).
  for (const char* name : {"heading", "start_sonar", "stop_sonar"}) {
    ASSERT_TRUE(c.find(name)) << name;
    EXPECT_EQ(Kind::Exec, c.find(name)->kind) << name;
  }
  for (const char* name : {"heading_reached", "target_detected"}) {
    ASSERT_TRUE(c.find(name)) << name;
    EXPECT_EQ(Kind::Ask, c.find(name)->kind) << name;
  }
  // + heading, sonar (4); open water: 8 exec (next_waypoint included), 3 ask;
  // set_sway (issue 20); set_timer, loiter, hold_position, start_rows,
  // next_row, gps_available, rows_done (issue 37).
  EXPECT_EQ(figure10.size() + 5 + 11 + 1 + 7, c.all().size());
  for (const char* name : {"set_timer", "loiter", "hold_position", "start_rows", "next_row"}) {
    ASSERT_TRUE(c.find(name)) << name;
    EXPECT_EQ(Kind::Exec, c.find(name)->kind) << name;
  }
  for (const char* name : {"gps_available", "rows_done"}) {
    ASSERT_TRUE(c.find(name)) << name;
    EXPECT_EQ(Kind::Ask, c.find(name)->kind) << name;
  }
  ASSERT_EQ(6u, c.find("start_rows")->args.size());
  ASSERT_TRUE(c.find("set_sway"));
  EXPECT_EQ(Kind::Exec, c.find("set_sway")->kind);
  EXPECT_EQ("exec set_sway {mps}", c.find("set_sway")->message);
  EXPECT_EQ("exec heading {degrees}", c.find("heading")->message);
  EXPECT_EQ(nullptr, c.find("exec_submerge"));  // CORAL names carry no prefix

  const Primitive& sleep = *c.find("sleep");
  ASSERT_EQ(1u, sleep.args.size());
  EXPECT_EQ("seconds", sleep.args[0].name);
  EXPECT_EQ("s", sleep.args[0].unit);
  EXPECT_EQ(0.1, sleep.args[0].min);
  EXPECT_EQ(3600, sleep.args[0].max);
  EXPECT_EQ("exec sleep {seconds}", sleep.message);
  EXPECT_EQ(DataSource::Setpoint, c.find("next_setpt_data")->data);
  EXPECT_EQ("exec setpoint {depth_m} {timeout_s}", c.find("next_setpt_data")->message);
  EXPECT_EQ("ood shutdown_network", c.find("shutdown_network")->message);
  EXPECT_EQ("", c.find("report")->message);
}

TEST(Catalogue, PrologPredicatesFollowFigure10) {
  const Catalogue& c = Catalogue::builtin();
  EXPECT_EQ("exec_next_setpt_data/1", c.find("next_setpt_data")->prolog_predicate());
  EXPECT_EQ("exec_sleep/2", c.find("sleep")->prolog_predicate());
  EXPECT_EQ("ask_depth_reached/1", c.find("depth_reached")->prolog_predicate());
  EXPECT_EQ("ood/2", c.find("shutdown_network")->prolog_predicate());
  EXPECT_EQ("report/1", c.find("report")->prolog_predicate());
  EXPECT_EQ("exec_sleep(Seconds, X)", c.find("sleep")->prolog_call());
  EXPECT_EQ("exec_submerge(X)", c.find("submerge")->prolog_call());
  EXPECT_EQ("ask_time_out(X)", c.find("time_out")->prolog_call());
  EXPECT_EQ("ood('shutdown_network', X)", c.find("shutdown_network")->prolog_call());
  EXPECT_EQ("report(Text)", c.find("report")->prolog_call());
}

TEST(Catalogue, EmbeddedTextIsTheConfigFile) {
  EXPECT_EQ(read(kSourceDir + "/config/primitives.toml"), Catalogue::builtin_text());
}

TEST(Catalogue, LoadsFromAPath) {
  auto c = Catalogue::load(kSourceDir + "/config/primitives.toml");
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_EQ(Catalogue::builtin().all().size(), c.value().all().size());
  EXPECT_EQ(kSourceDir + "/config/primitives.toml", c.value().source());

  auto missing = Catalogue::load(kSourceDir + "/config/no_such_file.toml");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(core::ErrorCode::Io, missing.error().code);
  EXPECT_NE(std::string::npos, missing.error().message.find("no_such_file.toml"));
}

TEST(Catalogue, SyntaxErrorsCarryLineAndColumn) {
  EXPECT_EQ(0u, parse_error("[[primitive]]\nname = \"x\"\nkind = \n").rfind("cat.toml:3:", 0));
  EXPECT_EQ(0u, parse_error("[[primitive]]\nname = \"x\"\nname = \"y\"\n").rfind("cat.toml:3:", 0));
}

const std::string kGood =
    "[[primitive]]\n"
    "name = \"sleep\"\n"
    "kind = \"exec\"\n"
    "args = [{ name = \"seconds\", type = \"number\", unit = \"s\", min = 0.1 }]\n"
    "timeout_s = 2\n"
    "doc = \"wait\"\n"
    "message = \"exec sleep {seconds}\"\n";

TEST(Catalogue, AMinimalFileParses) {
  auto c = Catalogue::parse(kGood, "cat.toml");
  ASSERT_TRUE(c.ok()) << c.error().message;
  ASSERT_EQ(1u, c.value().all().size());
  EXPECT_EQ(1u, c.value().all()[0].line);
}

TEST(Catalogue, SemanticErrorsAreLocated) {
  std::string bad_kind = kGood;
  bad_kind.replace(bad_kind.find("\"exec\""), 6, "\"run\"");
  EXPECT_EQ("cat.toml:3:8: primitive 'sleep': unknown kind 'run': expected exec, ask, ood or report",
            parse_error(bad_kind));

  EXPECT_EQ("cat.toml:10:8: duplicate primitive 'sleep' (first declared at line 1)", parse_error(kGood + "\n" + kGood));

  std::string bad_placeholder = kGood;
  bad_placeholder.replace(bad_placeholder.find("{seconds}"), 9, "{second}");
  EXPECT_EQ(
      "cat.toml:7:11: primitive 'sleep': placeholder {second} in the message names no argument (it "
      "knows: seconds)\n"
      "cat.toml:7:11: primitive 'sleep': argument 'seconds' does not appear in the message; write "
      "{seconds} where it goes",
      parse_error(bad_placeholder));

  EXPECT_EQ(
      "cat.toml:8:1: primitive 'sleep': unknown key 'colour' (known: args, data, doc, kind, "
      "message, name, reply_s, timeout_plus_arg, timeout_s)",
      parse_error(kGood + "colour = \"red\"\n"));
}

TEST(Catalogue, ShapeErrors) {
  auto has = [](const std::string& text, const std::string& what) {
    std::string e = parse_error(text);
    EXPECT_NE(std::string::npos, e.find(what)) << e;
  };
  has("", "cat.toml:1:1: no [[primitive]] tables");
  has("primitive = []\n", "cat.toml:1:13: the catalogue lists no primitive");
  has("primitive = 3\n", "cat.toml:1:13: 'primitive' must be an array of tables");
  has("[[primitive]]\nname = \"a\"\nkind = \"ask\"\ndoc = \"d\"\nmessage = \"ask a\"\n",
      "cat.toml:1:1: primitive 'a' has no 'timeout_s'");
  has("[[primitive]]\nname = \"a\"\nkind = \"ask\"\ndoc = \"d\"\ntimeout_s = 0\nmessage = \"ask a\"\n",
      "cat.toml:5:13: primitive 'a': timeout_s must be a number of seconds above 0");
  has("[[primitive]]\nname = \"a\"\nkind = \"ask\"\ndoc = \"d\"\ntimeout_s = 1\nmessage = \"exec a\"\n",
      "cat.toml:6:11: primitive 'a': the message must start with the verb 'ask'");
  has("[[primitive]]\nname = \"a\"\nkind = \"ask\"\ndoc = \"d\"\ntimeout_s = 1\nmessage = \"ask a {x\"\n",
      "cat.toml:6:11: primitive 'a': '{' at byte 7 of the message is never closed");
  has("[[primitive]]\nname = \"a\"\nkind = \"ask\"\ndoc = \"d\"\ntimeout_s = 1\n",
      "cat.toml:1:1: primitive 'a' has no 'message'");
  has("[[primitive]]\nname = \"r\"\nkind = \"report\"\ndoc = \"d\"\nmessage = \"report r\"\n",
      "cat.toml:5:11: primitive 'r': a report sends nothing to the vehicle, so it has no message");
  has("[[primitive]]\nname = \"a\"\nkind = \"exec\"\ndoc = \"d\"\ntimeout_s = 1\n"
      "message = \"exec a {depth_m}\"\n",
      "setpoint fields need data = \"setpoint\"");
  has("[[primitive]]\nname = \"a b\"\n", "cat.toml:2:8: primitive name 'a b' is not an identifier");
  has(kGood + "timeout_plus_arg = \"other\"\n",
      "cat.toml:8:20: primitive 'sleep': timeout_plus_arg 'other' must name a number argument");
  has("[[primitive]]\nname = \"a\"\nkind = \"exec\"\ndoc = \"d\"\ntimeout_s = 1\n"
      "message = \"exec a {x}\"\nargs = [{ name = \"x\", type = \"integer\" }]\n",
      "cat.toml:7:30: primitive 'a', argument 'x': unknown type 'integer'");
  has("[[primitive]]\nname = \"a\"\nkind = \"exec\"\ndoc = \"d\"\ntimeout_s = 1\n"
      "message = \"exec a {x}\"\nargs = [{ name = \"x\", type = \"number\" }]\n",
      "cat.toml:7:9: primitive 'a', argument 'x' has no 'unit'");
  has("[[primitive]]\nname = \"a\"\nkind = \"exec\"\ndoc = \"d\"\ntimeout_s = 1\n"
      "message = \"exec a {x} {y}\"\nargs = [{ name = \"x\", type = \"string\", default = \"q\" },\n"
      "        { name = \"y\", type = \"string\" }]\n",
      "cat.toml:8:9: primitive 'a', argument 'y': an argument without a default cannot follow");
  has("[[primitive]]\nname = \"a\"\nkind = \"exec\"\ndoc = \"d\"\ntimeout_s = 1\n"
      "message = \"exec a {x}\"\nargs = [{ name = \"x\", type = \"number\", unit = \"m\", min = 2, "
      "max = 1 }]\n",
      "primitive 'a', argument 'x': min 2 is above max 1");
}

TEST(CataloguePrint, TableListsEveryPrimitiveWithUnits) {
  std::string table = format_catalogue(Catalogue::builtin());
  EXPECT_EQ(0u, table.rfind("NAME", 0));
  EXPECT_NE(std::string::npos, table.find("sleep "));
  EXPECT_NE(std::string::npos, table.find("seconds (s, 0.1..3600)"));
  EXPECT_NE(std::string::npos, table.find("2 s + seconds"));
  EXPECT_NE(std::string::npos, table.find("text (string)"));
  EXPECT_NE(std::string::npos, table.find("ood('start_network', X)"));
  EXPECT_NE(std::string::npos, table.find("38 primitives from <builtin>/config/primitives.toml"));
  // A header, 38 rows, a blank line and the source line.
  EXPECT_EQ(41, std::count(table.begin(), table.end(), '\n'));
}

TEST(CataloguePrint, Json) {
  auto j = catalogue_json(Catalogue::builtin());
  ASSERT_EQ(38u, j["primitives"].size());
  const auto& sleep = j["primitives"][4];
  EXPECT_EQ(R"({"name":"sleep","kind":"exec","args":[{"name":"seconds","type":"number","unit":"s","min":0.1,)"
            R"("max":3600.0}],"timeout_s":2.0,"timeout_plus_arg":"seconds","prolog":"exec_sleep/2",)"
            R"("doc":"Let the vehicle run for the given time, then reply","message":"exec sleep {seconds}"})",
            sleep.dump());
  EXPECT_EQ("report", j["primitives"][37]["kind"]);
  EXPECT_FALSE(j["primitives"][37].contains("message"));
}

TEST(Catalogue, AFifoGivenAsTheCatalogueIsAnErrorNotAHang) {
  const auto fifo = core::testing::make_fifo("primitives.toml");
  ASSERT_FALSE(fifo.empty());
  auto r = Catalogue::load(fifo.string());
  std::filesystem::remove_all(fifo.parent_path());
  ASSERT_FALSE(r);
  EXPECT_EQ(core::ErrorCode::Io, r.error().code);
  EXPECT_NE(r.error().message.find("not a regular file"), std::string::npos) << r.error().message;
}

}  // namespace
// The timing analysis's reply bound (docs/verification.md, "Reaction time"):
// a primitive's own, else the catalogue's, else its timeout; never above it.
TEST(Catalogue, ReplyBoundsComeFromThePrimitiveTheCatalogueOrTheTimeout) {
  const std::string text = R"(reply_s = 0.5
[[primitive]]
name = "a"
kind = "ask"
timeout_s = 2
doc = "a"
message = "ask a"
[[primitive]]
name = "b"
kind = "ask"
timeout_s = 2
reply_s = 0.2
doc = "b"
message = "ask b"
[[primitive]]
name = "c"
kind = "ask"
timeout_s = 0.3
doc = "c"
message = "ask c"
)";
  auto c = Catalogue::parse(text, "cat.toml");
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_DOUBLE_EQ(0.5, c.value().reply_bound_s(*c.value().find("a")));
  EXPECT_DOUBLE_EQ(0.2, c.value().reply_bound_s(*c.value().find("b")));
  EXPECT_DOUBLE_EQ(0.3, c.value().reply_bound_s(*c.value().find("c")));
  const Catalogue& builtin = Catalogue::builtin();
  EXPECT_DOUBLE_EQ(0.1, builtin.reply_bound_s(*builtin.find("system_problem")));
}

TEST(Catalogue, AReplyBoundPastTheTimeoutOrNotAboveZeroIsRefused) {
  auto late = Catalogue::parse(
      "[[primitive]]\nname = \"a\"\nkind = \"ask\"\ntimeout_s = 2\nreply_s = 3\ndoc = \"a\"\nmessage = \"ask a\"\n",
      "cat.toml");
  ASSERT_FALSE(late.ok());
  EXPECT_NE(std::string::npos,
            late.error().message.find("cat.toml:5:11: primitive 'a': reply_s (3 s) must not exceed timeout_s (2 s)"))
      << late.error().message;
  auto zero = Catalogue::parse(
      "reply_s = 0\n[[primitive]]\nname = \"a\"\nkind = \"ask\"\ntimeout_s = 2\ndoc = \"a\"\nmessage = \"ask a\"\n",
      "cat.toml");
  ASSERT_FALSE(zero.ok());
  EXPECT_NE(std::string::npos, zero.error().message.find("cat.toml:1:11: reply_s must be a number of seconds above 0"))
      << zero.error().message;
}

}  // namespace strata::tactical
