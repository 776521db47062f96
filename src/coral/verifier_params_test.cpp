// Issue 20: parameters are data, not structure. A mission whose phase takes
// parameters verifies as its hand-expanded copy, where each call has a net
// of its own with the numbers written in: the same states, edges and
// verdicts, and the parameterised phase is verified once.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "coral/test_support.h"
#include "coral/verifier.h"
#include "coral/verifier_test_support.h"
#include "coral/verify_report.h"

namespace strata::coral {
namespace {

VerifyReport verify(const std::string& text) { return testing::verify_text_mission(text); }

// What a verification found, without the net's name: sizes, reachable exits
// and each property's verdict.
std::string shape(const NetVerification& n) {
  std::string out =
      fmt::format("{} places {} transitions {} states {} edges", n.places, n.transitions, n.states, n.edges);
  for (bool reachable : n.exit_reachable) out += reachable ? " exit" : " no-exit";
  for (const auto& p : n.properties) out += fmt::format(" {}={}", p.key, static_cast<int>(p.status));
  return out;
}

const NetVerification& net(const VerifyReport& r, std::string_view name) {
  for (const auto& n : r.nets) {
    if (n.name == name) return n;
  }
  throw std::runtime_error("no net " + std::string(name));
}

constexpr const char* kParameterised = R"(
net turn(deg, seconds) { place s = 1, turned, checked; exit done, failed;
  transition turn  { wait { s } action { TACTIC(EXEC, heading(deg), turned) } }
  transition check { wait { turned } action { TACTIC(ASK, q, checked, failed) } }
  transition hold  { wait { checked } action { TACTIC(EXEC, sleep(seconds), done) } } }
mission m { place begin = 1, a, b, lost; exit completed, aborted;
  transition one  { wait { begin } action { PHASE(turn(90, 1), a, lost) } }
  transition two  { wait { a } action { PHASE(turn(180, 2.5), b, lost) } }
  transition home { wait { b } signal { completed } }
  transition fail { wait { lost } signal { aborted } } }
)";

constexpr const char* kExpanded = R"(
net turn_90 { place s = 1, turned, checked; exit done, failed;
  transition turn  { wait { s } action { TACTIC(EXEC, heading(90), turned) } }
  transition check { wait { turned } action { TACTIC(ASK, q, checked, failed) } }
  transition hold  { wait { checked } action { TACTIC(EXEC, sleep(1), done) } } }
net turn_180 { place s = 1, turned, checked; exit done, failed;
  transition turn  { wait { s } action { TACTIC(EXEC, heading(180), turned) } }
  transition check { wait { turned } action { TACTIC(ASK, q, checked, failed) } }
  transition hold  { wait { checked } action { TACTIC(EXEC, sleep(2.5), done) } } }
mission m { place begin = 1, a, b, lost; exit completed, aborted;
  transition one  { wait { begin } action { PHASE(turn_90, a, lost) } }
  transition two  { wait { a } action { PHASE(turn_180, b, lost) } }
  transition home { wait { b } signal { completed } }
  transition fail { wait { lost } signal { aborted } } }
)";

TEST(VerifierParameters, AParameterisedMissionVerifiesAsItsHandExpandedCopy) {
  VerifyReport p = verify(kParameterised);
  VerifyReport e = verify(kExpanded);
  ASSERT_EQ(2u, p.nets.size()) << "one net for the phase, whatever its arguments";
  ASSERT_EQ(3u, e.nets.size());
  EXPECT_TRUE(p.ok()) << verify_text(p);
  EXPECT_EQ(e.ok(), p.ok());
  EXPECT_EQ(e.all_hold(), p.all_hold());
  EXPECT_EQ(shape(net(e, "m")), shape(net(p, "m")));
  EXPECT_EQ(shape(net(e, "turn_90")), shape(net(p, "turn")));
  EXPECT_EQ(shape(net(e, "turn_180")), shape(net(p, "turn")));
}

}  // namespace
}  // namespace strata::coral
