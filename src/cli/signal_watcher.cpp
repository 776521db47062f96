#include "cli/signal_watcher.h"

#include <pthread.h>
#include <signal.h>

#include <ctime>

namespace strata::cli {
namespace {

bool ignored(int signal) {
  struct sigaction current {};
  return sigaction(signal, nullptr, &current) == 0 && current.sa_handler == SIG_IGN;
}

// SIGTERM always; SIGINT and SIGHUP unless the process was started with them
// ignored (a background job of a script; nohup), which is the starter's word.
sigset_t stop_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGTERM);
  if (!ignored(SIGINT)) sigaddset(&set, SIGINT);
  if (!ignored(SIGHUP)) sigaddset(&set, SIGHUP);
  return set;
}

}  // namespace

SignalWatcher::SignalWatcher(std::function<void(int)> handler) : handler_(std::move(handler)) {
  const sigset_t set = stop_signals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  ::signal(SIGPIPE, SIG_IGN);
  thread_ = std::thread([this, set] {
    // A bounded wait: quit_ is seen even if the wake-up below were lost.
    const timespec tick{0, 100'000'000};
    while (!quit_) {
      siginfo_t info;
      const int signal = sigtimedwait(&set, &info, &tick);
      if (signal > 0 && !quit_) handler_(signal);
    }
  });
}

SignalWatcher::~SignalWatcher() {
  quit_ = true;
  // Wakes it now rather than at its next tick: SIGTERM sent to the watcher
  // thread alone, which takes it and sees quit_.
  if (thread_.joinable()) {
    // NOLINTNEXTLINE(bugprone-bad-signal-to-kill-thread): it waits for SIGTERM in sigwait, it is not killed
    pthread_kill(thread_.native_handle(), SIGTERM);
    thread_.join();
  }
}

std::string signal_name(int signal) {
  switch (signal) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "signal " + std::to_string(signal);
  }
}

}  // namespace strata::cli
