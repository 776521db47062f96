#include "prolog/engine.h"

#include <gtest/gtest.h>

namespace strata::prolog {
namespace {

class PrologEngine : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { ASSERT_TRUE(initialise().ok()); }
};

TEST_F(PrologEngine, GoalsSucceedFailOrRaise) {
  EXPECT_TRUE(call_once("X = 1, X == 1").value());
  EXPECT_FALSE(call_once("1 == 2").value());
  auto r = call_once("throw(my_error(42))");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ("my_error(42)", r.error().message) << "the exception keeps its term's text";
}

TEST_F(PrologEngine, UndefinedPredicateIsAnErrorNotTheDebugger) {
  auto r = call_once("no_such_predicate_here(1)");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(std::string::npos, r.error().message.find("existence_error")) << r.error().message;
}

TEST_F(PrologEngine, HaltInARuleDoesNotEndTheHost) {
  ASSERT_TRUE(call_once("assertz((stop_now :- halt))").value());
  auto r = call_once("stop_now");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ("strata_halt", r.error().message);
  r = call_once("halt(3)");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ("strata_halt(3)", r.error().message);
  EXPECT_TRUE(call_once("true").value()) << "still running";
}

TEST_F(PrologEngine, EndlessRecursionHitsTheStackLimit) {
  ASSERT_TRUE(call_once("assertz((deeper(N) :- M is N + 1, deeper(M), true))").value());
  auto r = call_once("deeper(0)");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(std::string::npos, r.error().message.find("resource_error")) << r.error().message.substr(0, 200);
}

TEST_F(PrologEngine, SyntaxErrorInGoalTextIsInvalidInput) {
  auto r = call_once("foo(");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(core::ErrorCode::InvalidInput, r.error().code);
}

// A foreign predicate that yields: the query hands control back to the host
// (Status::Yield), which resumes it later with the answer.
int g_answer = 0;
int g_yields = 0;
foreign_t answer_later(term_t x, control_t h) {
  static int token;
  switch (PL_foreign_control(h)) {
    case PL_FIRST_CALL: ++g_yields; PL_yield_address(&token);
    case PL_RESUME: return PL_unify_integer(x, g_answer);
    default: return TRUE;
  }
}

TEST_F(PrologEngine, ForeignYieldHandsControlBackAndResumes) {
  PL_register_foreign("answer_later", 1, reinterpret_cast<pl_function_t>(answer_later), PL_FA_NONDETERMINISTIC);
  ASSERT_TRUE(call_once("assertz((count_to(N, N) :- !)), "
                        "assertz((count_to(I, N) :- answer_later(X), J is I + X, count_to(J, N)))")
                  .value());
  Frame frame;
  auto goal = parse_term("count_to(0, 5)");
  ASSERT_TRUE(goal.ok());
  Query q(goal.value(), true);
  int resumes = 0;
  Query::Status s;
  g_yields = 0;
  while ((s = q.next()) == Query::Status::Yield && resumes < 100) {
    g_answer = 1;  // the host's answer, given before resuming
    ++resumes;
  }
  EXPECT_EQ(Query::Status::Last, s);
  EXPECT_EQ(5, resumes);
  EXPECT_EQ(5, g_yields);
}

}  // namespace
}  // namespace strata::prolog
