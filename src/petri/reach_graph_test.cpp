#include "petri/reach_graph.h"

#include <string>

#include <gtest/gtest.h>

#include "petri/dump.h"
#include "petri/net_families.h"

namespace strata::petri {
namespace {

std::string names(const Net& net, const std::vector<TransitionId>& path) {
  std::string s;
  for (TransitionId t : path) s += (s.empty() ? "" : " ") + std::string(net.transition_name(t));
  return s;
}

Marking marking_of(const ReachGraph& g, StateId s) {
  auto m = g.marking(s);
  return {m.begin(), m.end()};
}

TEST(ReachGraph, KeepsEveryEdgeAndTheShortestPathToEachState) {
  // start -> a -> b -> end by the long way, start -> end by the short one.
  NetBuilder b;
  PlaceId start = b.add_place("start", 1);
  PlaceId a = b.add_place("a");
  PlaceId c = b.add_place("b");
  PlaceId end = b.add_place("end");
  auto arc = [&](const char* name, PlaceId from, PlaceId to) {
    TransitionId t = b.add_transition(name);
    b.add_input(t, from);
    b.add_output(t, to);
  };
  arc("long1", start, a);
  arc("long2", a, c);
  arc("long3", c, end);
  arc("short", start, end);
  Net net = std::move(b).build();
  ReachGraph g = build_reach_graph(net);
  EXPECT_TRUE(g.complete());
  EXPECT_EQ(4u, g.state_count());
  EXPECT_EQ(4u, g.edge_count());
  for (StateId s = 0; s < g.state_count(); ++s) {
    const std::string m = dump_marking(net, marking_of(g, s));
    if (m == "end:1") {
      EXPECT_EQ("short", names(net, g.path_to(s)));
      EXPECT_TRUE(g.successors(s).empty());
    }
    if (m == "b:1") {
      EXPECT_EQ("long1 long2", names(net, g.path_to(s)));
    }
  }
  EXPECT_EQ(2u, g.successors(0).size());
}

TEST(ReachGraph, AMarkedTerminalPlaceEndsTheRun) {
  NetBuilder b;
  PlaceId p = b.add_place("p", 1);
  PlaceId exit = b.add_place("exit");
  PlaceId q = b.add_place("q");
  TransitionId t = b.add_transition("t");
  b.add_input(t, p);
  b.add_output(t, exit);
  b.add_output(t, q);
  TransitionId u = b.add_transition("u");  // would fire after the exit
  b.add_input(u, q);
  Net net = std::move(b).build();
  ReachGraph g = build_reach_graph(net, ReachOptions{{exit}, 1000});
  EXPECT_EQ(2u, g.state_count());
  EXPECT_TRUE(g.terminal(1));
  EXPECT_TRUE(g.successors(1).empty());
  ReachGraph free = build_reach_graph(net);
  EXPECT_EQ(3u, free.state_count());
}

TEST(ReachGraph, FindsACoveringMarkingAndStopsOnAnUnboundedNet) {
  // p -> p + q: q grows for ever.
  NetBuilder b;
  PlaceId p = b.add_place("p", 1);
  PlaceId q = b.add_place("q");
  TransitionId t = b.add_transition("grow");
  b.add_input(t, p);
  b.add_output(t, p);
  b.add_output(t, q);
  Net net = std::move(b).build();
  ReachGraph g = build_reach_graph(net);
  EXPECT_FALSE(g.complete());
  EXPECT_EQ("the net is unbounded", g.stopped_why());
  ASSERT_TRUE(g.unbounded().has_value());
  EXPECT_EQ("p:1 q:1", dump_marking(net, marking_of(g, g.unbounded()->state)));
  EXPECT_EQ("p:1", dump_marking(net, marking_of(g, g.unbounded()->ancestor)));
  EXPECT_EQ("grow", names(net, g.path_to(g.unbounded()->state)));
}

TEST(ReachGraph, StopsAtTheStateLimit) {
  ReachGraph g = build_reach_graph(dining_philosophers(6), ReachOptions{{}, 100});
  EXPECT_FALSE(g.complete());
  EXPECT_EQ("more than 100 reachable markings", g.stopped_why());
  EXPECT_FALSE(g.unbounded().has_value());
}

TEST(ReachGraph, CountsTheClosedFormFamilies) {
  EXPECT_EQ(243u, build_reach_graph(dining_philosophers(5)).state_count());
  ReachGraph r = build_reach_graph(referendum(6));
  EXPECT_TRUE(r.complete());
  EXPECT_EQ(730u, r.state_count());
}

}  // namespace
}  // namespace strata::petri
