#include "petri/pnml.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "petri/dump.h"
#include "core/test_fifo.h"

namespace strata::petri {
namespace {

// Lines 1-4 are the header, so the body starts on line 5, column 1.
std::string pnml(std::string_view body, std::string_view type = "http://www.pnml.org/version-2009/grammar/ptnet") {
  return fmt::format(
      "<?xml version=\"1.0\"?>\n"
      "<pnml xmlns=\"http://www.pnml.org/version-2009/grammar/pnml\">\n"
      "<net id=\"n\" type=\"{}\">\n"
      "<page id=\"pg\">\n"
      "{}"
      "</page>\n</net>\n</pnml>\n",
      type, body);
}

PnmlNet parse_ok(const std::string& text) {
  auto r = parse_pnml(text, "t.pnml");
  if (!r) ADD_FAILURE() << r.error().message;
  return r ? std::move(r).value() : PnmlNet{};
}

std::string error_of(const std::string& text) {
  auto r = parse_pnml(text, "t.pnml");
  if (r) return "(no error)";
  EXPECT_EQ(core::ErrorCode::InvalidInput, r.error().code);
  return r.error().message;
}

// The net by index, names left out: "x0=[2 0] t0:in{0*3}out{1}".
std::string structure(const Net& net) {
  std::string s = "x0=[";
  for (Tokens m : net.initial_marking()) s += fmt::format("{} ", m);
  s += "]";
  for (TransitionId t = 0; t < net.transition_count(); ++t) {
    s += fmt::format(" t{}:in{{", t);
    for (const Arc& a : net.inputs(t)) s += fmt::format("{}*{} ", a.node, a.weight);
    s += "}out{";
    for (const Arc& a : net.outputs(t)) s += fmt::format("{}*{} ", a.node, a.weight);
    s += "}";
  }
  return s;
}

TEST(PnmlRead, MinimalNetHasWeightOneAndNoTokensByDefault) {
  PnmlNet n =
      parse_ok(pnml("<place id=\"p\"/><place id=\"q\"><initialMarking><text>2</text></initialMarking></place>\n"
                    "<transition id=\"t\"/>\n"
                    "<arc id=\"a1\" source=\"p\" target=\"t\"/><arc id=\"a2\" source=\"t\" target=\"q\"/>\n"));
  EXPECT_EQ("place p = 0\nplace q = 2\ntransition t: in{p} out{q}\n", dump_net(n.net));
  EXPECT_EQ(2u, n.net.arc_count());
  EXPECT_EQ("n", n.id);
  EXPECT_EQ("n", n.name);  // no <name>: the id
}

TEST(PnmlRead, IdsNameTheNodesAndLabelsKeepTheNames) {
  PnmlNet n = parse_ok(
      "<pnml xmlns=\"http://www.pnml.org/version-2009/grammar/pnml\">"
      "<net id=\"n1\" type=\"http://www.pnml.org/version-2009/grammar/ptnet\">"
      "<name><text>My net</text></name><page id=\"pg\">"
      "<place id=\"p1\"><name><text>ready</text><graphics/></name><graphics/></place>"
      "<place id=\"p2\"><name><text>ready</text></name></place>"
      "<place id=\"p3\"/>"
      "<transition id=\"t1\"><name><text> go &amp; stop </text></name><toolspecific tool=\"x\"/></transition>"
      "</page></net></pnml>");
  EXPECT_EQ("p1", n.net.place_name(0));
  EXPECT_EQ("p2", n.net.place_name(1));
  EXPECT_EQ((std::vector<std::string>{"ready", "ready", "p3"}), n.place_labels);
  EXPECT_EQ((std::vector<std::string>{" go & stop "}), n.transition_labels);
  EXPECT_EQ("n1", n.id);
  EXPECT_EQ("My net", n.name);
}

TEST(PnmlRead, PrefixedElementNamesMeanTheSame) {
  PnmlNet n = parse_ok(
      "<pnml:pnml xmlns:pnml=\"http://www.pnml.org/version-2009/grammar/pnml\">"
      "<pnml:net id=\"n\" type=\"http://www.pnml.org/version-2009/grammar/ptnet\"><pnml:page id=\"pg\">"
      "<pnml:place id=\"p\"><pnml:initialMarking><pnml:text>1</pnml:text></pnml:initialMarking></pnml:place>"
      "</pnml:page></pnml:net></pnml:pnml>");
  EXPECT_EQ("place p = 1\n", dump_net(n.net));
}

TEST(PnmlRead, NestedPagesAreReadInDocumentOrder) {
  PnmlNet n =
      parse_ok(pnml("<place id=\"a\"/>\n"
                    "<page id=\"inner\"><place id=\"b\"/><page id=\"deeper\"><transition id=\"t\"/></page>"
                    "<place id=\"c\"/></page>\n"
                    "<place id=\"d\"/>\n"
                    "<arc id=\"x\" source=\"d\" target=\"t\"/>\n"));
  EXPECT_EQ("place a = 0\nplace b = 0\nplace c = 0\nplace d = 0\ntransition t: in{d} out{}\n", dump_net(n.net));
}

TEST(PnmlRead, ReferenceNodesStandForTheNodeTheyReference) {
  // r2 -> r1 -> p is a chain; rt is defined before the transition it names.
  PnmlNet n = parse_ok(
      pnml("<page id=\"pg2\"><referencePlace id=\"r2\" ref=\"r1\"/><referenceTransition id=\"rt\" ref=\"t\"/>\n"
           "<arc id=\"a1\" source=\"r2\" target=\"rt\"><inscription><text>2</text></inscription></arc></page>\n"
           "<place id=\"p\"><initialMarking><text>1</text></initialMarking></place>\n"
           "<referencePlace id=\"r1\" ref=\"p\"/><place id=\"q\"/><transition id=\"t\"/>\n"
           "<arc id=\"a2\" source=\"rt\" target=\"q\"/>\n"));
  EXPECT_EQ("place p = 1\nplace q = 0\ntransition t: in{p*2} out{q}\n", dump_net(n.net));
  EXPECT_EQ(2u, n.net.place_count());  // references are no places of their own
}

TEST(PnmlRead, ParallelArcsAddUp) {
  PnmlNet n =
      parse_ok(pnml("<place id=\"p\"/><referencePlace id=\"rp\" ref=\"p\"/><transition id=\"t\"/>\n"
                    "<arc id=\"a1\" source=\"p\" target=\"t\"/>\n"
                    "<arc id=\"a2\" source=\"rp\" target=\"t\"><inscription><text>2</text></inscription></arc>\n"
                    "<arc id=\"a3\" source=\"t\" target=\"p\"/>\n"));
  EXPECT_EQ("place p = 0\ntransition t: in{p*3} out{p}\n", dump_net(n.net));
  EXPECT_EQ(2u, n.net.arc_count());  // the self-loop is one Pre and one Post arc
}

TEST(PnmlRead, NumbersMayHaveWhitespaceAndReachTheTokenLimit) {
  PnmlNet n =
      parse_ok(pnml("<place id=\"p\"><initialMarking><text>\n  4294967295\t</text></initialMarking></place>\n"
                    "<transition id=\"t\"/>\n"
                    "<arc id=\"a\" source=\"p\" target=\"t\"><inscription><text> 7 </text></inscription></arc>\n"));
  EXPECT_EQ("place p = 4294967295\ntransition t: in{p*7} out{}\n", dump_net(n.net));
}

TEST(PnmlRead, UnsupportedNetTypesAreErrors) {
  EXPECT_EQ(
      "t.pnml:3:1: net type 'http://www.pnml.org/version-2009/grammar/symmetricnet' is not "
      "supported: Strata reads P/T nets (ptnet)",
      error_of(pnml("", "http://www.pnml.org/version-2009/grammar/symmetricnet")));
  EXPECT_EQ(
      "t.pnml:3:1: net type 'http://www.pnml.org/version-2009/grammar/pnmlcoremodel' is not "
      "supported: Strata reads P/T nets (ptnet)",
      error_of(pnml("", "http://www.pnml.org/version-2009/grammar/pnmlcoremodel")));
  EXPECT_EQ("t.pnml:2:2: <net> has no type: Strata reads P/T nets (ptnet)",
            error_of("<pnml>\n <net id=\"n\"><page id=\"p\"/></net></pnml>"));
}

TEST(PnmlRead, InhibitorReadAndResetArcsAreErrors) {
  for (std::string type : {"inhibitor", "read", "reset"}) {
    EXPECT_EQ("t.pnml:7:3: " + type + " arc 'a' is not supported: Strata reads P/T nets (ptnet)",
              error_of(pnml("<place id=\"p\"/><transition id=\"t\"/>\n"
                            "<arc id=\"a\" source=\"p\" target=\"t\">\n"
                            "  <type value=\"" +
                            type + "\"/></arc>\n")));
  }
}

TEST(PnmlRead, ArcsMustJoinAPlaceAndAKnownTransition) {
  std::string nodes = "<place id=\"p\"/><place id=\"q\"/><transition id=\"t\"/><transition id=\"u\"/>\n";
  EXPECT_EQ("t.pnml:6:1: arc 'a' joins two places: an arc joins a place and a transition",
            error_of(pnml(nodes + "<arc id=\"a\" source=\"p\" target=\"q\"/>\n")));
  EXPECT_EQ("t.pnml:6:1: arc 'a' joins two transitions: an arc joins a place and a transition",
            error_of(pnml(nodes + "<arc id=\"a\" source=\"t\" target=\"u\"/>\n")));
  EXPECT_EQ("t.pnml:6:1: arc 'a' has target 'zz', which does not exist",
            error_of(pnml(nodes + "<arc id=\"a\" source=\"p\" target=\"zz\"/>\n")));
  EXPECT_EQ("t.pnml:6:1: arc 'a' has source 'pg', which is a page",
            error_of(pnml(nodes + "<arc id=\"a\" source=\"pg\" target=\"t\"/>\n")));
  EXPECT_EQ("t.pnml:6:1: arc 'a' has no target", error_of(pnml(nodes + "<arc id=\"a\" source=\"p\"/>\n")));
}

TEST(PnmlRead, BadMarkingsAndInscriptionsAreErrors) {
  auto marking = [](std::string_view text) {
    return error_of(
        pnml(fmt::format("<place id=\"p\">\n<initialMarking><text>{}</text></initialMarking></place>\n", text)));
  };
  EXPECT_EQ("t.pnml:6:1: initial marking of place 'p' is '-1', not a non-negative integer", marking("-1"));
  EXPECT_EQ("t.pnml:6:1: initial marking of place 'p' is '1.5', not a non-negative integer", marking("1.5"));
  EXPECT_EQ("t.pnml:6:1: initial marking of place 'p' is '', not a non-negative integer", marking(""));
  EXPECT_EQ("t.pnml:6:1: initial marking of place 'p' is over the limit of 4294967295", marking("4294967296"));
  EXPECT_EQ("t.pnml:6:1: initial marking of place 'p' is over the limit of 4294967295",
            marking("99999999999999999999999999"));
  auto inscription = [](std::string_view text) {
    return error_of(
        pnml(fmt::format("<place id=\"p\"/><transition id=\"t\"/>\n"
                         "<arc id=\"a\" source=\"p\" target=\"t\">\n"
                         " <inscription><text>{}</text></inscription></arc>\n",
                         text)));
  };
  EXPECT_EQ("t.pnml:7:2: inscription of arc 'a' is '0', not a positive integer", inscription("0"));
  EXPECT_EQ("t.pnml:7:2: inscription of arc 'a' is 'x', not a positive integer", inscription("x"));
  EXPECT_EQ("t.pnml:7:2: inscription of arc 'a' is over the limit of 4294967295", inscription("4294967296"));
  EXPECT_EQ("t.pnml:7:1: arc 'b' and the arcs parallel to it weigh over 4294967295 in all",
            error_of(pnml("<place id=\"p\"/><transition id=\"t\"/>\n"
                          "<arc id=\"a\" source=\"p\" target=\"t\"><inscription><text>4294967295</text>"
                          "</inscription></arc>\n<arc id=\"b\" source=\"p\" target=\"t\"/>\n")));
}

TEST(PnmlRead, DanglingAndCyclicReferencesAreErrors) {
  EXPECT_EQ("t.pnml:5:1: referencePlace 'r' refers to 'nowhere', which does not exist",
            error_of(pnml("<referencePlace id=\"r\" ref=\"nowhere\"/>\n")));
  EXPECT_EQ("t.pnml:6:1: referencePlace 'r2' is part of a reference cycle",
            error_of(pnml("<referencePlace id=\"r1\" ref=\"r2\"/>\n"
                          "<referencePlace id=\"r2\" ref=\"r1\"/>\n")));
  EXPECT_EQ("t.pnml:5:1: referenceTransition 'r' is part of a reference cycle",
            error_of(pnml("<referenceTransition id=\"r\" ref=\"r\"/>\n")));
  EXPECT_EQ("t.pnml:6:1: referencePlace 'r' refers to transition 't', not to a place",
            error_of(pnml("<transition id=\"t\"/>\n<referencePlace id=\"r\" ref=\"t\"/>\n")));
  EXPECT_EQ("t.pnml:5:1: referenceTransition 'r' has no ref", error_of(pnml("<referenceTransition id=\"r\"/>\n")));
}

TEST(PnmlRead, StructuralErrorsNameTheirLine) {
  EXPECT_EQ("t.pnml:6:1: duplicate id 'p' (first used at 5:1)",
            error_of(pnml("<place id=\"p\"/>\n<transition id=\"p\"/>\n")));
  EXPECT_EQ("t.pnml:5:1: <place> has no id", error_of(pnml("<place/>\n")));
  EXPECT_EQ("t.pnml:5:1: <declaration> is not part of a P/T net", error_of(pnml("<declaration/>\n")));
  EXPECT_EQ("t.pnml:5:15: <capacity> in place 'p' is not part of a P/T net",
            error_of(pnml("<place id=\"p\"><capacity><text>3</text></capacity></place>\n")));
  EXPECT_EQ("t.pnml:3:1: a second <net>: Strata reads one net per PNML file",
            error_of("<pnml>\n<net id=\"a\" type=\"http://www.pnml.org/version-2009/grammar/ptnet\"/>\n"
                     "<net id=\"b\" type=\"http://www.pnml.org/version-2009/grammar/ptnet\"/>\n</pnml>\n"));
  EXPECT_EQ("t.pnml:1:1: the PNML document holds no <net>", error_of("<pnml/>"));
}

TEST(PnmlRead, NonPnmlAndMalformedXmlAreErrors) {
  EXPECT_EQ("t.pnml:2:1: not a PNML document: the root element is <html>, not <pnml>",
            error_of("<?xml version=\"1.0\"?>\n<html><body/></html>\n"));
  EXPECT_EQ("t.pnml:6:3: malformed XML: Start-end tags mismatch", error_of(pnml("<place id=\"p\">\n</transition>\n")));
  EXPECT_EQ("t.pnml:1:1: malformed XML: No document element found", error_of(""));
  // pugixml puts this one past the end of the text: reported at the end.
  EXPECT_EQ("t.pnml:2:7: malformed XML: Error parsing element attribute", error_of("<pnml>\n<net a"));
}

TEST(PnmlRead, MissingFileIsAnIoError) {
  auto r = read_pnml("/nonexistent/dir/model.pnml");
  ASSERT_FALSE(r);
  EXPECT_EQ(core::ErrorCode::Io, r.error().code);
  EXPECT_NE(std::string::npos, r.error().message.find("/nonexistent/dir/model.pnml"));
  auto dir = read_pnml("/tmp");
  ASSERT_FALSE(dir);
  EXPECT_EQ(core::ErrorCode::Io, dir.error().code);
}

TEST(PnmlWrite, RoundTripKeepsTheNetAndOddNamesComeBackAsLabels) {
  NetBuilder b;
  PlaceId p0 = b.add_place("a b", 3);
  PlaceId p1 = b.add_place("x<y", 0);
  PlaceId p2 = b.add_place("a_b", 4294967295u);  // the id "a b" would also become
  PlaceId p3 = b.add_place("9lives & \"quotes\"\r\n\x01", 1);
  PlaceId p4 = b.add_place("", 0);
  TransitionId t0 = b.add_transition("a b");  // a place's name
  TransitionId t1 = b.add_transition("t1");
  TransitionId t2 = b.add_transition("t1");  // a duplicate
  b.add_input(t0, p0, 2);
  b.add_input(t0, p1);
  b.add_output(t0, p2, 5);
  b.add_input(t1, p2, 4294967295u);
  b.add_output(t1, p3);
  b.add_input(t2, p3);
  b.add_output(t2, p3, 7);  // self-loop with different weights
  b.add_output(t2, p4);
  Net net = std::move(b).build();

  std::string text = write_pnml(net, "my net");
  auto back = parse_pnml(text, "written.pnml");
  ASSERT_TRUE(back) << back.error().message << "\n" << text;
  const PnmlNet& n = back.value();
  EXPECT_EQ(structure(net), structure(n.net));
  EXPECT_EQ(net.arc_count(), n.net.arc_count());
  EXPECT_EQ((std::vector<std::string>{"a b", "x<y", "a_b", "9lives & \"quotes\"\r\n\x01", ""}), n.place_labels);
  EXPECT_EQ((std::vector<std::string>{"a b", "t1", "t1"}), n.transition_labels);
  EXPECT_EQ("my net", n.name);
  // Ids: XML names, unique across the document.
  EXPECT_EQ("a_b", n.net.place_name(0));
  EXPECT_EQ("x_y", n.net.place_name(1));
  EXPECT_EQ("a_b_2", n.net.place_name(2));
  EXPECT_EQ("_9lives____quotes____", n.net.place_name(3));
  EXPECT_EQ("_", n.net.place_name(4));
  EXPECT_EQ("a_b_3", n.net.transition_name(0));
  EXPECT_EQ("t1", n.net.transition_name(1));
  EXPECT_EQ("t1_2", n.net.transition_name(2));
  EXPECT_EQ("my_net", n.id);
}

TEST(PnmlWrite, PlainNamesAreKeptAsIdsAndDefaultsAreLeftOut) {
  NetBuilder b;
  PlaceId p = b.add_place("p", 0);
  TransitionId t = b.add_transition("a1");  // the first arc id would be a1
  b.add_input(t, p);
  Net net = std::move(b).build();
  std::string text = write_pnml(net, "n");
  EXPECT_EQ(std::string::npos, text.find("initialMarking"));
  EXPECT_EQ(std::string::npos, text.find("inscription"));
  EXPECT_NE(std::string::npos, text.find("<arc id=\"a1_2\" source=\"p\" target=\"a1\"/>")) << text;
  EXPECT_EQ(dump_net(net), dump_net(parse_ok(text).net));
}

// ../shared/pnml: 23 MCC models with answers.csv (model,places,transitions,
// arcs,max_arc_weight,...).
TEST(PnmlCorpus, MccModelsMatchTheirAnswersAndRoundTrip) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(STRATA_SOURCE_DIR) / ".." / "shared" / "pnml";
  if (!fs::exists(dir / "answers.csv")) GTEST_SKIP() << "skipped: ../shared/pnml not present";
  std::ifstream csv(dir / "answers.csv");
  std::string line;
  std::getline(csv, line);
  ASSERT_EQ(0u, line.rfind("model,places,transitions,arcs,max_arc_weight,", 0)) << line;
  int models = 0;
  while (std::getline(csv, line)) {
    std::stringstream fields(line);
    std::string model, places, transitions, arcs, max_weight;
    std::getline(fields, model, ',');
    std::getline(fields, places, ',');
    std::getline(fields, transitions, ',');
    std::getline(fields, arcs, ',');
    std::getline(fields, max_weight, ',');
    SCOPED_TRACE(model);
    auto r = read_pnml((dir / model / "model.pnml").string());
    ASSERT_TRUE(r) << r.error().message;
    const Net& net = r.value().net;
    std::uint32_t heaviest = 0;
    for (TransitionId t = 0; t < net.transition_count(); ++t) {
      for (const Arc& a : net.inputs(t)) heaviest = std::max(heaviest, a.weight);
      for (const Arc& a : net.outputs(t)) heaviest = std::max(heaviest, a.weight);
    }
    EXPECT_EQ(places, std::to_string(net.place_count()));
    EXPECT_EQ(transitions, std::to_string(net.transition_count()));
    EXPECT_EQ(arcs, std::to_string(net.arc_count()));
    EXPECT_EQ(max_weight, std::to_string(heaviest));

    auto back = parse_pnml(write_pnml(net, r.value().id), "written.pnml");
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(dump_net(net), dump_net(back.value().net));
    EXPECT_EQ(r.value().id, back.value().id);
    ++models;
  }
  EXPECT_EQ(23, models);
}

TEST(PnmlRead, AFifoGivenAsInputIsAnErrorNotAHang) {
  const auto fifo = core::testing::make_fifo("net.pnml");
  ASSERT_FALSE(fifo.empty());
  auto r = read_pnml(fifo.string());
  std::filesystem::remove_all(fifo.parent_path());
  ASSERT_FALSE(r);
  EXPECT_EQ(core::ErrorCode::Io, r.error().code);
  EXPECT_NE(r.error().message.find("not a regular file"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace strata::petri
