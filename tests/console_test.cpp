// The operator's console (cli/console.h): a line repeated at one simulated
// instant (a loop that never waits) is shown three times, then counted.
#include "cli/console.h"

#include <sstream>

#include <gtest/gtest.h>

namespace strata::cli {
namespace {

TEST(Console, ALineRepeatedAtOneInstantIsShownThriceThenCounted) {
  std::ostringstream out;
  Console c(out, false);
  for (int i = 0; i < 10'000; ++i) c.report("again", 0.2);
  c.report("later", 0.3);                              // time moves: the count is said
  for (int i = 0; i < 3; ++i) c.report("again", 0.4);  // a new instant: shown again
  c.clear_status();
  const std::string text = out.str();
  EXPECT_EQ(
      "[    0.2 s] REPORT: again\n"
      "[    0.2 s] REPORT: again\n"
      "[    0.2 s] REPORT: again\n"
      "[    0.2 s] (lines repeating at this instant: the rest are counted, not shown)\n"
      "[    0.2 s] 9997 repeated lines not shown\n"
      "[    0.3 s] REPORT: later\n"
      "[    0.4 s] REPORT: again\n"
      "[    0.4 s] REPORT: again\n"
      "[    0.4 s] REPORT: again\n",
      text);
}

TEST(Console, LinesThatRepeatOverTimeAreAllShown) {
  std::ostringstream out;
  Console c(out, false);
  for (int i = 0; i < 20; ++i) c.report("leg done", i * 10.0);
  std::size_t lines = 0;
  for (char ch : out.str()) lines += ch == '\n';
  EXPECT_EQ(20u, lines);
}

}  // namespace
}  // namespace strata::cli
