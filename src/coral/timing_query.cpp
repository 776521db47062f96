// The timing analysis's questions (coral/timing.h): "FROM -> TO [within S]".
#include <cctype>
#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "coral/timing.h"

namespace strata::coral {
namespace {

// ------------------------------------------------------------------ the query

struct Cursor {
  std::string_view text;
  std::size_t pos = 0;
  void skip() {
    while (pos < text.size() && (text[pos] == ' ' || text[pos] == '\t')) ++pos;
  }
  // The next word (letters, digits, '_'), or "" (at the end or another character).
  std::string_view word() {
    skip();
    const std::size_t start = pos;
    while (pos < text.size() && (std::isalnum(static_cast<unsigned char>(text[pos])) != 0 || text[pos] == '_')) ++pos;
    return text.substr(start, pos - start);
  }
  core::Error error(std::size_t at, const std::string& message) const {
    return core::make_error(core::ErrorCode::InvalidInput, fmt::format("column {}: {}", at + 1, message));
  }
};

constexpr std::string_view kForms =
    "write FROM -> TO, FROM one of `fault ASK`, `fault not ASK`, `trip GUARD`, `start PHASE`, TO one of "
    "`exec NAME`, `ask NAME`, `ood NAME`, `call NAME`, `exit NAME`, `surface`, then optionally `within S`";

}  // namespace

core::Result<BoundQuery> parse_bound(std::string_view text) {
  Cursor c{text};
  BoundQuery q;
  q.text = std::string(text);
  c.skip();
  std::size_t at = c.pos;
  const std::string_view from = c.word();
  if (from == "fault") {
    q.from = BoundQuery::From::Fault;
  } else if (from == "trip") {
    q.from = BoundQuery::From::Trip;
  } else if (from == "start") {
    q.from = BoundQuery::From::Start;
  } else {
    return c.error(at, fmt::format("expected fault, trip or start: {}", kForms));
  }
  c.skip();
  at = c.pos;
  std::string_view name = c.word();
  if (q.from == BoundQuery::From::Fault && name == "not") {
    q.fault_value = false;
    c.skip();
    at = c.pos;
    name = c.word();
  }
  if (name.empty()) return c.error(at, fmt::format("expected a name after {}", from));
  q.from_name = std::string(name);
  c.skip();
  if (c.text.substr(c.pos, 2) != "->") return c.error(c.pos, fmt::format("expected ->: {}", kForms));
  c.pos += 2;
  c.skip();
  at = c.pos;
  const std::string_view to = c.word();
  if (to == "surface") {
    q.to = BoundQuery::To::Surface;
  } else if (to == "exit") {
    q.to = BoundQuery::To::Exit;
  } else if (to == "call" || to == "exec" || to == "ask" || to == "ood") {
    q.to = BoundQuery::To::Call;
    if (to != "call") q.to_verb = parse_tactic_type(to == "exec" ? "EXEC" : to == "ask" ? "ASK" : "OOD");
  } else {
    return c.error(at, fmt::format("expected exec, ask, ood, call, exit or surface: {}", kForms));
  }
  if (q.to != BoundQuery::To::Surface) {
    c.skip();
    at = c.pos;
    name = c.word();
    if (name.empty()) return c.error(at, fmt::format("expected a name after {}", to));
    q.to_name = std::string(name);
  }
  c.skip();
  at = c.pos;
  if (c.word() == "within") {
    c.skip();
    const std::size_t num = c.pos;
    std::size_t end = num;
    while (end < text.size() && (std::isdigit(static_cast<unsigned char>(text[end])) != 0 || text[end] == '.')) ++end;
    double v = 0;
    const auto [ptr, ec] = std::from_chars(text.data() + num, text.data() + end, v);
    if (ec != std::errc{} || ptr != text.data() + end || end == num || !(v > 0) || !std::isfinite(v)) {
      return c.error(num, "expected a number of seconds above 0 after within");
    }
    q.within_s = v;
    c.pos = end;
    c.skip();
    if (c.text.substr(c.pos, 1) == "s") ++c.pos;
    c.skip();
  } else {
    c.pos = at;
  }
  if (c.pos != c.text.size()) return c.error(c.pos, "unexpected text after the question");
  return q;
}

std::string_view bound_verdict_name(BoundAnswer::Verdict v) {
  switch (v) {
    case BoundAnswer::Verdict::Bounded: return "bounded";
    case BoundAnswer::Verdict::Unbounded: return "unbounded";
    case BoundAnswer::Verdict::NoEvent: return "no_event";
    case BoundAnswer::Verdict::Unsupported: return "unsupported";
  }
  return "unsupported";
}

}  // namespace strata::coral
