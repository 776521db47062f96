#include "petri/predicate.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace strata::petri {
namespace {

// p1, p2, p3 (initially 1, 0, 2) and one transition.
Net three_places() {
  NetBuilder b;
  PlaceId p1 = b.add_place("p1", 1);
  b.add_place("p2", 0);
  PlaceId p3 = b.add_place("p3", 2);
  TransitionId t = b.add_transition("t");
  b.add_input(t, p1);
  b.add_output(t, p3);
  return std::move(b).build();
}

std::string question_error_of(std::string_view text, const Net& net) {
  auto q = parse_question(text, net_place_resolver(net));
  return q ? std::string("ok") : q.error().text();
}

bool holds(std::string_view text, const Net& net, const Marking& m) {
  auto p = parse_predicate(text, net_place_resolver(net));
  EXPECT_TRUE(p.ok()) << (p ? "" : p.error().message);
  return p && p.value().holds(m);
}

TEST(Predicate, ComparesPlacesAndNumbers) {
  const Net net = three_places();
  const Marking m{1, 0, 2};
  EXPECT_TRUE(holds("p1 >= 1", net, m));
  EXPECT_FALSE(holds("p1 >= 2", net, m));
  EXPECT_TRUE(holds("p2 == 0 && p3 != 1", net, m));
  EXPECT_TRUE(holds("p3 > p1", net, m));
  EXPECT_TRUE(holds("2 <= p3", net, m));
  EXPECT_FALSE(holds("p3 < 2", net, m));
  EXPECT_TRUE(holds("p1 <= 1", net, m));
}

TEST(Predicate, NegationParenthesesAndPrecedence) {
  const Net net = three_places();
  const Marking m{1, 0, 2};
  EXPECT_TRUE(holds("p1 >= 2 || p2 == 0 && p3 == 2", net, m));  // && binds tighter
  EXPECT_FALSE(holds("(p1 >= 2 || p2 == 0) && p3 == 1", net, m));
  EXPECT_TRUE(holds("!(p1 >= 2)", net, m));
  EXPECT_FALSE(holds("!(p1 >= 1 && !(p3 == 0))", net, m));
  EXPECT_TRUE(holds("!!true", net, m));
  EXPECT_FALSE(holds("!true || false", net, m));
  EXPECT_TRUE(holds("!(p1 == 0 || p2 == 1)", net, m));
}

TEST(Predicate, NegatedIsTheComplementOnEveryMarking) {
  const Net net = three_places();
  auto p = parse_predicate("p1 >= 1 && !(p3 == 0) || p2 != p3 && false", net_place_resolver(net));
  ASSERT_TRUE(p.ok()) << p.error().message;
  const Predicate n = p.value().negated();
  for (Tokens a = 0; a < 3; ++a) {
    for (Tokens b = 0; b < 3; ++b) {
      for (Tokens c = 0; c < 3; ++c) {
        const Marking m{a, b, c};
        EXPECT_NE(p.value().holds(m), n.holds(m)) << a << b << c;
      }
    }
  }
}

TEST(Predicate, ToStringReadsBack) {
  const Net net = three_places();
  auto p = parse_predicate("!(p1 >= 2 || p3 == 0) && true", net_place_resolver(net));
  ASSERT_TRUE(p.ok());
  const std::string text = p.value().to_string(net);
  EXPECT_EQ("((p1 < 2 && p3 != 0) && true)", text);
  auto again = parse_predicate(text, net_place_resolver(net));
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_EQ(text, again.value().to_string(net));
}

TEST(Predicate, QuotedNamesAndLabels) {
  NetBuilder b;
  b.add_place("id-1", 3);
  b.add_place("id-2", 0);
  b.add_place("id-3", 0);
  Net net = std::move(b).build();
  const std::vector<std::string> labels{"Fork 1", "dup", "dup"};
  auto resolve = net_place_resolver(net, &labels);
  auto p = parse_predicate("\"Fork 1\" == 3 && id-2 == 0", resolve);
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_TRUE(p.value().holds(Marking{3, 0, 0}));
  auto dup = parse_predicate("dup >= 1", resolve);
  ASSERT_FALSE(dup.ok());
  EXPECT_EQ("column 1: 'dup' names 2 places (id-2, id-3): use an id", dup.error().text());
}

TEST(Question, Kinds) {
  const Net net = three_places();
  auto d = parse_question("  deadlock ", net_place_resolver(net));
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(QuestionKind::Deadlock, d.value().kind);
  auto ef = parse_question("EF p3 >= 3", net_place_resolver(net));
  ASSERT_TRUE(ef.ok());
  EXPECT_EQ(QuestionKind::Reachable, ef.value().kind);
  EXPECT_TRUE(ef.value().target.holds(Marking{0, 0, 3}));
  auto ag = parse_question("AG p1 + 0 == 1", net_place_resolver(net));
  EXPECT_FALSE(ag.ok());
  auto ag2 = parse_question("AG p1 <= 1", net_place_resolver(net));
  ASSERT_TRUE(ag2.ok());
  EXPECT_EQ(QuestionKind::Invariant, ag2.value().kind);
  EXPECT_TRUE(ag2.value().target.holds(Marking{2, 0, 0}));  // the target is the negation
  EXPECT_FALSE(ag2.value().target.holds(Marking{1, 0, 0}));
}

TEST(Question, ErrorsGiveTheColumn) {
  const Net net = three_places();
  EXPECT_EQ("column 4: no place 'p9'", question_error_of("EF p9 >= 1", net));
  EXPECT_EQ("column 7: '=' is not a comparison: write '=='", question_error_of("EF p1 = 1", net));
  EXPECT_EQ("column 20: expected ')' to close the '(' at column 4, found 'end of text'",
            question_error_of("EF (p1 >= 1 &&p2==0", net));
  EXPECT_EQ("column 12: unmatched ')'", question_error_of("EF p1 >= 1 )", net));
  EXPECT_EQ("column 3: expected a predicate", question_error_of("EF", net));
  EXPECT_EQ("column 1: a question is 'deadlock', 'EF <predicate>' or 'AG <predicate>', not 'EG'",
            question_error_of("EG p1 >= 1", net));
  EXPECT_EQ("column 10: nothing may follow 'deadlock'", question_error_of("deadlock p1", net));
  EXPECT_EQ("column 7: expected a comparison (== != < <= > >=) after 'p1', found '&&'",
            question_error_of("EF p1 && p2", net));
  EXPECT_EQ("column 10: negative numbers are not allowed: a place holds 0 or more tokens",
            question_error_of("EF p1 >= -1", net));
  EXPECT_EQ("column 10: number too large (at most 2^62)", question_error_of("EF p1 >= 99999999999999999999", net));
  EXPECT_EQ("column 4: unterminated quoted place name", question_error_of("EF \"p1 >= 1", net));
  EXPECT_EQ("column 12: unexpected 'p2' after the predicate", question_error_of("EF p1 >= 1 p2", net));
  EXPECT_EQ("column 10: expected a place name or a number, found '?'", question_error_of("EF p1 >= ?", net));
}

// Regression: the column was only inside the message, and `strata verify
// --question` read it back from the text to place its caret.
TEST(Question, TheColumnIsAFieldApartFromTheMessage) {
  const Net net = three_places();
  auto q = parse_question("EF p9 >= 1", net_place_resolver(net));
  ASSERT_FALSE(q.ok());
  EXPECT_EQ(4u, q.error().column);
  EXPECT_EQ(0u, q.error().line);
  EXPECT_EQ("no place 'p9'", q.error().message);
  EXPECT_EQ(core::ErrorCode::InvalidInput, q.error().to_core().code);
  EXPECT_EQ("column 4: no place 'p9'", q.error().to_core().message);
}

TEST(Question, DeepNestingIsAnErrorNotACrash) {
  const Net net = three_places();
  std::string deep = "EF " + std::string(5000, '(') + "true" + std::string(5000, ')');
  EXPECT_NE(std::string::npos, question_error_of(deep, net).find("nested more than"));
  std::string nots = "EF " + std::string(5000, '!') + "true";
  EXPECT_NE(std::string::npos, question_error_of(nots, net).find("nested more than"));
}

}  // namespace
}  // namespace strata::petri
