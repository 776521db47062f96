#pragma once
// A thin RAII layer over SWI-Prolog's C API (docs/prolog.md), used by the
// PROLOG Strategic level. SWI-Prolog has one engine per process here:
// initialise() starts it once (no signal handlers, a stack limit, no
// debugger, halt/0 and halt/1 made to throw strata_halt instead of ending
// the host, the interrupt of prolog/interrupt.h installed), and every other
// call must come from the thread that did (except prolog::interrupt()).
//
// Errors: a Prolog exception becomes a core::Error whose message keeps the
// exception term's text.
#include <SWI-Prolog.h>

#include <optional>
#include <string>
#include <string_view>

#include "core/result.h"

namespace strata::prolog {

struct EngineOptions {
  std::string stack_limit = "256m";  // SWI's --stack-limit: deep recursion ends in resource_error
};

// Starts the engine on the calling thread (once). A later call returns ok
// on that thread and an error on any other: SWI-Prolog has no engine there,
// and the first call into it from there would crash the process.
core::Result<void> initialise(const EngineOptions& options = {});
// Any thread.
bool initialised();

// The term as writeq/1 prints it.
std::string term_text(term_t t);

// A foreign frame: term references made inside it are released when it
// ends (discarded: bindings made inside are undone).
class Frame {
 public:
  Frame() : fid_(PL_open_foreign_frame()) {}
  ~Frame() { PL_discard_foreign_frame(fid_); }
  Frame(const Frame&) = delete;
  Frame& operator=(const Frame&) = delete;

 private:
  fid_t fid_;
};

// An open query. Opened with PL_Q_CATCH_EXCEPTION | PL_Q_EXT_STATUS, plus
// PL_Q_ALLOW_YIELD when asked (a foreign predicate may then yield and next()
// returns Status::Yield until resumed by another next()), plus PL_Q_NODEBUG
// unless exception_hook: SWI calls user:prolog_exception_hook/4 only for
// queries in debug mode (the debugger itself stays off: initialise() sets
// debug_on_error to false). Only one query is open at a time per nesting
// level (SWI's rule); the destructor cuts it.
class Query {
 public:
  enum class Status { True, Last, False, Exception, Yield };

  // Calls user:call(Goal) for goal, a term in the caller's frame.
  Query(term_t goal, bool allow_yield, bool exception_hook = false);
  ~Query();
  Query(const Query&) = delete;
  Query& operator=(const Query&) = delete;

  Status next();
  // After Status::Exception: the exception term's text.
  const std::string& exception_text() const { return exception_; }
  // Ends the query now (keeping bindings); next() may not be called after.
  void cut();

 private:
  qid_t qid_ = nullptr;
  bool open_ = false;
  std::string exception_;
};

// Parses text as a term into a new term reference (InvalidInput on a syntax error).
core::Result<term_t> parse_term(std::string_view text);

// Runs goal text once: true, false, or the exception as an error.
core::Result<bool> call_once(std::string_view goal);
// The same for a goal term (in the caller's frame; its bindings are kept).
core::Result<bool> call_term(term_t goal);

// A term's text when it is an atom, a string or a number; its writeq text otherwise.
std::string text_of(term_t t);

// PL_get_nchars(t, flags | BUF_STACK | REP_UTF8), copied out: nullopt when
// t has no text under flags. SWI-Prolog keeps BUF_STACK text on a stack of
// buffers that it releases when a foreign predicate returns to Prolog; the
// host's own calls (a Query's caller) never return there, so the text is
// released here, at once, or each call would grow that stack for the life
// of the process.
std::optional<std::string> get_text(term_t t, unsigned flags);

}  // namespace strata::prolog
