#include "prolog/engine.h"

#include <atomic>
#include <csignal>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "prolog/interrupt.h"

namespace strata::prolog {
namespace {

// Set once, on the engine's thread, g_started_on before g_initialised
// (not g_engine_thread: interrupt.cpp has one, and a unity build joins them):
// other threads read them (initialised(), and initialise() refusing them).
std::atomic<bool> g_initialised = false;
std::thread::id g_started_on;

constexpr int kQueryFlags = PL_Q_CATCH_EXCEPTION | PL_Q_EXT_STATUS;

// Rules must never end the host: halt/0,1 in module user throw instead, and
// the executor turns strata_halt into the end of the mission.
constexpr const char* kHaltGuard =
    "(redefine_system_predicate(user:halt), assertz((user:halt :- throw(strata_halt))),"
    " redefine_system_predicate(user:halt(_)), assertz((user:halt(C) :- throw(strata_halt(C)))))";

}  // namespace

core::Result<void> initialise(const EngineOptions& options) {
  if (g_initialised) {
    if (g_started_on == std::this_thread::get_id()) return {};
    return core::make_error(core::ErrorCode::Internal,
                            "SWI-Prolog was started on another thread of this process, and only that thread may "
                            "call it");
  }
  std::string stack = "--stack-limit=" + options.stack_limit;
  // SWI keeps argv; these strings live as long as the process.
  static std::vector<std::string> args;
  // Not --no-signals: SWI-Prolog's guard against running out of C stack
  // (a term nested 100,000 deep, written or read) is its SIGSEGV handler on
  // an alternate stack, which --no-signals leaves out: without it such a
  // term crashes the process. SWI's handlers for every other signal are
  // undone right after PL_initialise(): the host owns SIGINT, SIGTERM,
  // SIGHUP and the rest (the run's signal watcher), as under --no-signals.
  args = {"strata", "--no-packs", "--no-tty", "-q", stack};
  static std::vector<char*> argv;
  argv.clear();
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  struct sigaction before[NSIG];
  for (int sig = 1; sig < NSIG; ++sig) (void)sigaction(sig, nullptr, &before[sig]);
  if (!PL_initialise(static_cast<int>(args.size()), argv.data())) {
    return core::make_error(core::ErrorCode::Internal, "SWI-Prolog could not be initialised");
  }
  for (int sig = 1; sig < NSIG; ++sig) {
    // SIGSEGV and SIGBUS: the C-stack guard. SIGUSR2: SWI's alert signal,
    // which prolog/interrupt.h knocks with (installed under --no-signals too).
    if (sig == SIGSEGV || sig == SIGBUS || sig == SIGUSR2 || sig == SIGKILL || sig == SIGSTOP) continue;
    (void)sigaction(sig, &before[sig], nullptr);
  }
  g_started_on = std::this_thread::get_id();
  g_initialised = true;
  // Queries that run the exception hook are not PL_Q_NODEBUG: an uncaught
  // error must still never start the debugger.
  if (auto r = call_once("set_prolog_flag(debug_on_error, false)"); !r || !r.value()) {
    return core::make_error(core::ErrorCode::Internal, "could not turn off debug_on_error in SWI-Prolog");
  }
  auto guard = call_once(kHaltGuard);
  if (!guard || !guard.value()) {
    return core::make_error(core::ErrorCode::Internal, "could not guard halt/0 in SWI-Prolog");
  }
  return install_interrupt();
}

bool initialised() { return g_initialised; }

std::optional<std::string> get_text(term_t t, unsigned flags) {
  std::optional<std::string> text;
  buf_mark_t mark;
  PL_mark_string_buffers(&mark);
  char* s = nullptr;
  std::size_t len = 0;
  if (PL_get_nchars(t, &len, &s, flags | BUF_STACK | REP_UTF8)) text.emplace(s, len);
  PL_release_string_buffers_from_mark(mark);
  return text;
}

std::string term_text(term_t t) {
  if (auto text = get_text(t, CVT_WRITEQ | CVT_EXCEPTION)) return *std::move(text);
  PL_clear_exception();
  return "<term>";
}

Query::Query(term_t goal, bool allow_yield, bool exception_hook) {
  static predicate_t call1 = PL_predicate("call", 1, "user");
  const int flags = kQueryFlags | (allow_yield ? PL_Q_ALLOW_YIELD : 0) | (exception_hook ? 0 : PL_Q_NODEBUG);
  qid_ = PL_open_query(nullptr, flags, call1, goal);
  open_ = qid_ != nullptr;
}

Query::~Query() { cut(); }

Query::Status Query::next() {
  if (!open_) return Status::False;
  switch (PL_next_solution(qid_)) {
    case PL_S_TRUE: return Status::True;
    case PL_S_LAST: return Status::Last;
    case PL_S_YIELD: return Status::Yield;
    case PL_S_EXCEPTION: {
      term_t ex = PL_exception(qid_);
      exception_ = ex ? term_text(ex) : std::string("unknown exception");
      return Status::Exception;
    }
    default: return Status::False;
  }
}

void Query::cut() {
  if (!open_) return;
  PL_cut_query(qid_);
  open_ = false;
}

core::Result<term_t> parse_term(std::string_view text) {
  term_t t = PL_new_term_ref();
  std::string s(text);
  if (!PL_chars_to_term(s.c_str(), t)) {
    // On a syntax error t holds the exception term.
    std::string why = term_text(t);
    return core::make_error(core::ErrorCode::InvalidInput, fmt::format("cannot read `{}`: {}", text, why));
  }
  return t;
}

core::Result<bool> call_once(std::string_view goal) {
  Frame frame;
  auto t = parse_term(goal);
  if (!t) return t.error();
  return call_term(t.value());
}

std::string text_of(term_t t) {
  if (auto text = get_text(t, CVT_ATOMIC)) return *std::move(text);
  return term_text(t);
}

core::Result<bool> call_term(term_t goal) {
  Query q(goal, false);
  switch (q.next()) {
    case Query::Status::True:
    case Query::Status::Last: return true;
    case Query::Status::False: return false;
    case Query::Status::Exception: return core::make_error(core::ErrorCode::InvalidInput, q.exception_text());
    case Query::Status::Yield:
      return core::make_error(core::ErrorCode::Internal, "a foreign predicate yielded outside a mission query");
  }
  return false;
}

}  // namespace strata::prolog
