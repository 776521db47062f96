#pragma once
// Stopping the query that runs on the engine's thread from another thread
// (a thread that watches for SIGINT, an HTTP worker): docs/prolog.md §3.
//
// The query raises strata_interrupted at its next call port, also when it
// is busy in a loop (every call is a port) or waiting in sleep/1 (SWI-
// Prolog handles signals when the wait returns EINTR, then fails with the
// exception). driver.pl makes the exception one the rules cannot catch.
//
// How it works, and why it is safe:
//  - A Prolog-only signal (PL_sigaction(0, ...): a number above the OS
//    signals, so no OS signal is taken) whose handler raises the exception.
//    SWI runs the handler synchronously on the engine's thread at a point
//    where the engine is consistent (PLSIG_SYNC); the handler raises only
//    when an interrupt is armed, so a stale raise does nothing.
//  - interrupt() marks it pending with PL_thread_raise(), which takes SWI's
//    own locks and is meant to be called from other threads.
//  - A POSIX timer sends SIGUSR2 to the engine's thread right away and then
//    every kKnockInterval until the query returns: a blocking system call
//    (sleep/1's nanosleep) returns EINTR, and SWI looks at the pending raise.
//    SIGUSR2 is SWI-Prolog's own "alert" signal: it installs an empty
//    handler for it without SA_RESTART even under --no-signals, for this
//    purpose. The repeat closes the race where the first knock lands just
//    before the thread enters the system call. Nothing here runs in a
//    signal handler but SWI's empty one.
//
// Threads: install_interrupt() and InterruptScope on the engine's thread;
// interrupt() on any thread, including the engine's own (not in a signal
// handler: it takes a lock, which the engine's thread holds only briefly).
#include <chrono>

#include "core/result.h"

namespace strata::prolog {

inline constexpr std::chrono::milliseconds kKnockInterval{10};

// Called once by initialise(), on the engine's thread.
core::Result<void> install_interrupt();

// Open on the engine's thread while a query runs (around PL_next_solution):
// while it lives, interrupt(owner) stops that query. Scopes do not nest.
class InterruptScope {
 public:
  explicit InterruptScope(const void* owner);
  // Stops the knocking; a raise the query did not handle is dropped, so it
  // cannot reach the next query.
  ~InterruptScope();
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;

  // The handler raised strata_interrupted in this scope's query.
  bool interrupted() const;
};

// From any thread. When a scope of owner is open: raises
// strata_interrupted in its query (soon: at the next call port, or when a
// blocking call returns on the knock) and returns true; each call raises
// once more, so a second interrupt also stops rules that a first one left
// looping in a recovery goal. When none is open (owner waits for the
// vehicle, or has ended): does nothing, returns false. Never waits for the
// query.
bool interrupt(const void* owner);

}  // namespace strata::prolog
