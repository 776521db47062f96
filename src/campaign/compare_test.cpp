// --compare: two results files matched by inputs, the changes sorted out.
#include "campaign/compare.h"

#include <gtest/gtest.h>

#include "campaign/campaign_test_support.h"

namespace strata::campaign {
namespace {

std::string line(int index, double at_s, bool pass, const std::string& outcome, double t) {
  return nlohmann::json{{"index", index},
                        {"inputs",
                         {{"mission", "tank.coral"},
                          {"family", "leak"},
                          {"fault", {{"kind", "leak"}, {"at_s", at_s}}},
                          {"seed", 1}}},
                        {"outcome", outcome},
                        {"pass", pass},
                        {"checks", {{{"name", "surface_within_s"}, {"pass", pass}, {"figure", t}}}}}
             .dump() +
         "\n";
}

TEST(CampaignCompare, CasesAreMatchedByInputsAndEachChangeIsNamed) {
  testing::TempDir dir;
  const std::string a = dir.write("a.jsonl", line(0, 1, true, "aborted", 4.0) + line(1, 2, true, "aborted", 5.0) +
                                                 line(2, 3, false, "failed", 20.0) + line(3, 9, true, "aborted", 1.0));
  // B: a case added at the front moves every index; case at 2 s now fails,
  // 3 s passes, 1 s surfaces later, 9 s is gone.
  const std::string b = dir.write("b.jsonl", line(0, 0.5, true, "aborted", 1.0) + line(1, 1, true, "aborted", 4.5) +
                                                 line(2, 2, false, "failed", 16.0) + line(3, 3, true, "aborted", 6.0));
  auto r = compare_results(a, b);
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(3u, r.value().matched);
  EXPECT_TRUE(r.value().differs());
  ASSERT_EQ(1u, r.value().newly_failing.size());
  EXPECT_EQ("1 -> 2: tank.coral · leak · leak at_s=2.0 · seed 1 (failed; surface_within_s 16.0)",
            r.value().newly_failing[0]);
  ASSERT_EQ(1u, r.value().newly_passing.size());
  EXPECT_EQ(2u, r.value().outcome_changed.size());
  ASSERT_EQ(1u, r.value().figure_changed.size());
  EXPECT_EQ("0 -> 1: tank.coral · leak · leak at_s=1.0 · seed 1: surface_within_s 4.0 -> 4.5",
            r.value().figure_changed[0]);
  EXPECT_EQ(1u, r.value().only_a.size());
  EXPECT_EQ(1u, r.value().only_b.size());

  auto same = compare_results(a, a);
  ASSERT_TRUE(same.ok());
  EXPECT_FALSE(same.value().differs());
  EXPECT_TRUE(same.value().figure_changed.empty());
}

TEST(CampaignCompare, ALineThatIsNotAResultIsLocated) {
  testing::TempDir dir;
  const std::string a = dir.write("a.jsonl", line(0, 1, true, "aborted", 4.0) + "{\"index\": 3}\n");
  auto r = compare_results(a, a);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(a + ":2: not a line of a campaign's results.jsonl", r.error().message);
  EXPECT_EQ(core::ErrorCode::Io, compare_results(dir.file("none.jsonl"), a).error().code);
}

}  // namespace
}  // namespace strata::campaign
