#include "prolog/interrupt.h"

#include <SWI-Prolog.h>
#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>

#include <fmt/format.h>

namespace strata::prolog {
namespace {

constexpr int kKnockSignal = SIGUSR2;

std::atomic<bool> g_installed{false};
int g_signal = 0;         // the Prolog-only signal
int g_engine_thread = 0;  // the engine's thread, as PL_thread_self() names it
timer_t g_knock{};        // sends kKnockSignal to the engine's thread

// Guards the open scope's owner and whether it was raised; the engine's
// thread holds it only to open and close a scope, never while Prolog runs.
std::mutex g_mutex;
const void* g_owner = nullptr;
bool g_raised = false;

// The handler's view, on the engine's thread: it must not take g_mutex (an
// interrupting thread may hold it while it raises).
std::atomic<bool> g_armed{false};
std::atomic<bool> g_delivered{false};

// Runs on the engine's thread at a call port (or when a blocking wait
// returned EINTR), with the engine consistent: PLSIG_SYNC.
void raise_interrupted(int) {
  // Disarmed: a raise left pending by a scope that closed first.
  if (!g_armed.exchange(false)) return;
  g_delivered = true;
  term_t ex = PL_new_term_ref();
  // SWI throws it when the handler returns (PL_raise_exception() returns
  // FALSE by design).
  if (ex && PL_put_atom_chars(ex, "strata_interrupted")) (void)PL_raise_exception(ex);
}

void set_knocking(bool on) {
  itimerspec spec{};
  if (on) {
    spec.it_value.tv_nsec = 1;  // at once; 0 would disarm
    spec.it_interval.tv_nsec = std::chrono::nanoseconds(kKnockInterval).count();
  }
  (void)timer_settime(g_knock, 0, &spec, nullptr);
}

void do_nothing(int) {}

}  // namespace

core::Result<void> install_interrupt() {
  if (g_installed) return {};
  // A knock must never take the default action (which ends the process) nor
  // be ignored (the wait would go on). SWI-Prolog has its alert handler
  // there; otherwise ours, also without SA_RESTART.
  struct sigaction current {};
  if (sigaction(kKnockSignal, nullptr, &current) != 0) {
    return core::make_error(core::ErrorCode::Internal, "cannot read the SIGUSR2 handler");
  }
  if (!(current.sa_flags & SA_SIGINFO) && (current.sa_handler == SIG_DFL || current.sa_handler == SIG_IGN)) {
    struct sigaction knock {};
    knock.sa_handler = do_nothing;
    sigemptyset(&knock.sa_mask);
    if (sigaction(kKnockSignal, &knock, nullptr) != 0) {
      return core::make_error(core::ErrorCode::Internal, "cannot install a SIGUSR2 handler");
    }
  }

  pl_sigaction_t act{};
  act.sa_cfunction = raise_interrupted;
  act.sa_flags = PLSIG_SYNC;
  int sig = PL_sigaction(0, &act, nullptr);
  if (sig <= 0) {
    return core::make_error(core::ErrorCode::Internal, "SWI-Prolog has no free signal for the interrupt");
  }

  sigevent event{};
  event.sigev_notify = SIGEV_THREAD_ID;
  event.sigev_signo = kKnockSignal;
  event._sigev_un._tid = gettid();  // sigev_notify_thread_id, which this glibc does not name
  if (timer_create(CLOCK_MONOTONIC, &event, &g_knock) != 0) {
    return core::make_error(core::ErrorCode::Internal,
                            fmt::format("cannot create the interrupt's timer: {}", std::strerror(errno)));
  }
  g_signal = sig;
  g_engine_thread = PL_thread_self();
  g_installed = true;
  return {};
}

InterruptScope::InterruptScope(const void* owner) {
  std::lock_guard lock(g_mutex);
  g_owner = owner;
  g_raised = false;
  g_armed = false;
  g_delivered = false;
}

InterruptScope::~InterruptScope() {
  std::lock_guard lock(g_mutex);
  // Disarmed before the scope ends: a raise the query did not reach stays
  // pending in SWI (its C API cannot clear one) and is handled, as nothing,
  // at the next call port of whatever Prolog runs next.
  g_armed = false;
  g_owner = nullptr;
  if (g_raised) set_knocking(false);
  g_raised = false;
}

bool InterruptScope::interrupted() const { return g_delivered; }

bool interrupt(const void* owner) {
  if (!g_installed || owner == nullptr) return false;
  std::lock_guard lock(g_mutex);
  if (g_owner != owner) return false;
  g_armed = true;
  if (!PL_thread_raise(g_engine_thread, g_signal)) {
    g_armed = false;
    return false;
  }
  if (!g_raised) set_knocking(true);
  g_raised = true;
  return true;
}

}  // namespace strata::prolog
