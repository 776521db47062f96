#include <gtest/gtest.h>

#include "petri/dump.h"
#include "petri/net.h"

namespace strata::petri {
namespace {

// The paper's Figure 2 style example: p1 --2--> t1 --> p2, with a self-loop
// on p3.
Net small_net() {
  NetBuilder b;
  PlaceId p1 = b.add_place("p1", 2);
  PlaceId p2 = b.add_place("p2");
  PlaceId p3 = b.add_place("p3", 1);
  TransitionId t1 = b.add_transition("t1");
  TransitionId t2 = b.add_transition("t2", 5);
  b.add_input(t1, p1, 2);
  b.add_output(t1, p2);
  b.add_input(t1, p3);
  b.add_output(t1, p3);  // self-loop
  b.add_input(t2, p2);
  b.add_output(t2, p1);
  b.add_output(t2, p1);  // given twice: merged into weight 2
  return std::move(b).build();
}

TEST(Net, KeepsPreAndPostSeparately) {
  Net net = small_net();
  EXPECT_EQ(3u, net.place_count());
  EXPECT_EQ(2u, net.transition_count());
  EXPECT_EQ(2u, net.pre_weight(0, 0));
  EXPECT_EQ(1u, net.pre_weight(2, 0));
  EXPECT_EQ(1u, net.post_weight(2, 0));
  EXPECT_EQ(2u, net.post_weight(0, 1));  // merged
  EXPECT_EQ(6u, net.arc_count());        // Pre 3 + Post 3 (the doubled arc merged)
}

TEST(Net, IncidenceIsPostMinusPreAndSelfLoopsCancel) {
  Net net = small_net();
  EXPECT_EQ(-2, net.incidence(0, 0));
  EXPECT_EQ(1, net.incidence(1, 0));
  EXPECT_EQ(0, net.incidence(2, 0));  // self-loop: C says 0, yet p3 gates t1
  EXPECT_EQ("p1: -2 2\np2: 1 -1\np3: 0 0\n", dump_incidence(net));
}

TEST(Net, EnablingUsesPreNotIncidence) {
  Net net = small_net();
  Marking m = {2, 0, 0};  // p3 empty: the self-loop must disable t1
  EXPECT_FALSE(is_enabled(net, m, 0));
  m[2] = 1;
  EXPECT_TRUE(is_enabled(net, m, 0));
  m[0] = 1;  // below the weight 2
  EXPECT_FALSE(is_enabled(net, m, 0));
}

TEST(Net, ReadersAndWritersIndexThePlaces) {
  Net net = small_net();
  ASSERT_EQ(1u, net.readers(0).size());
  EXPECT_EQ(0u, net.readers(0)[0].node);
  EXPECT_EQ(2u, net.readers(0)[0].weight);
  ASSERT_EQ(1u, net.writers(0).size());
  EXPECT_EQ(1u, net.writers(0)[0].node);
}

TEST(Net, FindsByName) {
  Net net = small_net();
  EXPECT_EQ(1u, net.find_place("p2"));
  EXPECT_EQ(1u, net.find_transition("t2"));
  EXPECT_FALSE(net.find_place("nope"));
  Net copy = net;  // lookups stay valid in a copy
  EXPECT_EQ(2u, copy.find_place("p3"));
}

TEST(Dump, NetAndMarkingAreStableText) {
  Net net = small_net();
  EXPECT_EQ(
      "place p1 = 2\nplace p2 = 0\nplace p3 = 1\n"
      "transition t1: in{p1*2, p3} out{p2, p3}\n"
      "transition t2 priority 5: in{p2} out{p1*2}\n",
      dump_net(net));
  EXPECT_EQ("p1:2 p3:1", dump_marking(net, net.initial_marking()));
  EXPECT_EQ("(empty)", dump_marking(net, {0, 0, 0}));
}

}  // namespace
}  // namespace strata::petri
