// Hostile inputs for arguments and phase parameters: each gives a clear,
// located error (or none), never a crash or a hang.
#include <chrono>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "coral/parser.h"
#include "coral/test_support.h"

namespace strata::coral {
namespace {

using testing::compile_text;

// heading(deg) in 0..360 deg, as the catalogue says; nothing else.
CheckOptions heading_only() {
  CheckOptions o;
  o.primitive = [](std::string_view name) -> std::optional<PrimitiveSignature> {
    if (name != "heading") return std::nullopt;
    return PrimitiveSignature{ast::TacticType::Exec, 1, 1, {{"degrees", true, "deg", 0.0, 360.0}}};
  };
  o.primitive_names = {"heading"};
  return o;
}

std::string mission_calling(const std::string& call) {
  return "mission m { place b = 1; exit done;\n  transition t { wait { b } action { " + call + " } } }\n";
}

std::string many(std::size_t n, const std::string& item) {
  std::string out;
  for (std::size_t i = 0; i < n; ++i) out += (i ? ", " : "") + fmt::format(fmt::runtime(item), i);
  return out;
}

TEST(Arguments, TenThousandArgumentsToAPhaseAreOneError) {
  auto c = compile_text(
      "net p(x) { place s = 1; exit e; transition t { wait { s } action { TACTIC(EXEC, heading(x), e) } } }\n" +
          mission_calling("PHASE(p(" + many(10'000, "1") + "), done)"),
      {}, heading_only());
  EXPECT_FALSE(c->program);
  EXPECT_EQ((std::vector<std::string>{fmt::format("3:{} TooManyArguments", 46 + 3 * kMaxArguments)}), c->kinds());
}

TEST(Arguments, TenThousandArgumentsToAPrimitiveAreOneError) {
  auto c = compile_text(mission_calling("TACTIC(EXEC, heading(" + many(10'000, "{}") + "), done)"), {}, heading_only());
  EXPECT_FALSE(c->program);
  ASSERT_EQ(1u, c->kinds().size());
  EXPECT_TRUE(c->kinds()[0].ends_with("TooManyArguments")) << c->kinds()[0];
}

TEST(Arguments, TenThousandParametersAreOneError) {
  auto c = compile_text(
      "net p(" + many(10'000, "x{}") + ") { place s = 1; exit e; transition t { wait { s } signal { e } } }\n", {},
      heading_only());
  EXPECT_FALSE(c->program);
  ASSERT_EQ(1u, c->kinds().size());
  EXPECT_TRUE(c->kinds()[0].ends_with("TooManyArguments")) << c->kinds()[0];
}

TEST(Arguments, HugeAndNanLookingNumbersAreLocatedErrors) {
  const std::string digits(4000, '9');
  auto c = compile_text(
      "net n { place s = 1, a, b, c, d; exit e;\n"
      "  transition t1 { wait { s } action { TACTIC(EXEC, heading(1e999), a) } }\n"
      "  transition t2 { wait { a } action { TACTIC(EXEC, heading(" +
          digits +
          "), b) } }\n"
          "  transition t3 { wait { b } action { TACTIC(EXEC, heading(nan), c) } }\n"
          "  transition t4 { wait { c } action { TACTIC(EXEC, heading(-inf), d) } }\n"
          "  transition t5 { wait { d } action { TACTIC(EXEC, heading(1e308), e) } } }\n",
      {}, heading_only());
  EXPECT_FALSE(c->program);
  // -inf is no token CORAL has: a lexical error, and the file is not checked.
  EXPECT_EQ((std::vector<std::string>{"5:60 InvalidCharacter"}), c->kinds());
  auto d = compile_text(
      "net n { place s = 1, a, b, c; exit e;\n"
      "  transition t1 { wait { s } action { TACTIC(EXEC, heading(1e999), a) } }\n"
      "  transition t2 { wait { a } action { TACTIC(EXEC, heading(" +
          digits +
          "), b) } }\n"
          "  transition t3 { wait { b } action { TACTIC(EXEC, heading(nan), c) } }\n"
          "  transition t5 { wait { c } action { TACTIC(EXEC, heading(1e308), e) } } }\n",
      {}, heading_only());
  EXPECT_FALSE(d->program);
  EXPECT_EQ((std::vector<std::string>{"2:60 ArgumentOutOfRange", "3:60 ArgumentOutOfRange", "4:60 UnknownParameter",
                                      "5:60 ArgumentOutOfRange"}),
            d->kinds());
}

// A chain of 5,000 phases, each passing its parameter to the next, the last
// using it in heading(): the call at the top is checked against heading's
// range, in time linear in the chain (the engine and the verifier stop such
// a mission at the phase depth limit; the checker only has to stay quick).
TEST(Arguments, ADeepChainOfParameterisedPhasesIsCheckedAtTheTopQuickly) {
  constexpr int kDepth = 5000;
  std::string text;
  for (int i = 0; i < kDepth; ++i) {
    text += fmt::format(
        "net p{}(x) {{ place s = 1; exit e; transition t {{ wait {{ s }} action {{ PHASE(p{}(x), e) }} }} }}\n", i,
        i + 1);
  }
  text += fmt::format(
      "net p{}(x) {{ place s = 1; exit e; transition t {{ wait {{ s }} action {{ TACTIC(EXEC, heading(x), e) }} }} "
      "}}\n",
      kDepth);
  text += mission_calling("PHASE(p0(400), done)");
  auto start = std::chrono::steady_clock::now();
  auto c = compile_text(text, {}, heading_only());
  auto took = std::chrono::steady_clock::now() - start;
  EXPECT_FALSE(c->program);
  EXPECT_EQ((std::vector<std::string>{fmt::format("{}:47 ArgumentOutOfRange", kDepth + 3)}), c->kinds());
  EXPECT_LT(took, std::chrono::seconds(10));
}

// Each net calls the next twice: 2^60 paths, but each net is visited once.
TEST(Arguments, ADiamondOfPhasesIsNotExploredPathByPath) {
  constexpr int kDepth = 60;
  std::string text;
  for (int i = 0; i < kDepth; ++i) {
    text += fmt::format(
        "net p{0}(x) {{ place s = 1, m; exit e; transition t {{ wait {{ s }} action {{ PHASE(p{1}(x), m) }} }}\n"
        "  transition u {{ wait {{ m }} action {{ PHASE(p{1}(x), e) }} }} }}\n",
        i, i + 1);
  }
  text += fmt::format(
      "net p{}(x) {{ place s = 1; exit e; transition t {{ wait {{ s }} action {{ TACTIC(EXEC, heading(x), e) }} }} "
      "}}\n",
      kDepth);
  text += mission_calling("PHASE(p0(-1), done)");
  auto c = compile_text(text, {}, heading_only());
  EXPECT_FALSE(c->program);
  ASSERT_EQ(1u, c->kinds().size());
  EXPECT_TRUE(c->kinds()[0].ends_with("ArgumentOutOfRange")) << c->kinds()[0];
}

}  // namespace
}  // namespace strata::coral
