#include "prolog/engine.h"

#include <malloc.h>

#include <cstddef>
#include <string>

#include <gtest/gtest.h>
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
// The sanitizers' allocators keep their own count (GCC ships no header for it).
extern "C" std::size_t __sanitizer_get_current_allocated_bytes();
#endif

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

namespace strata::prolog {
namespace {

// Bytes the allocator has handed out and not had back.
std::size_t heap_in_use() {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  return __sanitizer_get_current_allocated_bytes();
#else
  return ::mallinfo2().uordblks;
#endif
}

// Regression: the host's reads of a term's text (text_of, term_text) left
// the text on SWI-Prolog's stack of string buffers, which only a return to
// Prolog releases and the host never makes: a campaign worker's memory grew
// by about 0.5 KB a case, for as long as it ran.
TEST_F(PrologEngine, TextTheHostReadsIsReleased) {
  Frame frame;
  auto t = parse_term("'" + std::string(4096, 'x') + "'");
  ASSERT_TRUE(t);
  auto c = parse_term("f(" + std::string(2048, 'y') + ")");
  ASSERT_TRUE(c);
  EXPECT_EQ(4096u, text_of(t.value()).size());
  const std::size_t before = heap_in_use();
  for (int i = 0; i < 5000; ++i) {
    ASSERT_EQ(4096u, text_of(t.value()).size());
    ASSERT_EQ(2051u, text_of(c.value()).size());  // its writeq text
  }
  // Kept, the texts would be 5000 x 6 KB, 30 MB.
  EXPECT_LT(heap_in_use(), before + (std::size_t{1} << 20));
}

}  // namespace
}  // namespace strata::prolog
