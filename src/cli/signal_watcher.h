#pragma once
// The operator's signals during a run: SIGINT (Ctrl-C), SIGTERM and SIGHUP
// (the terminal closed) are taken by a thread of their own with sigwait, so
// that they reach the run even while the event loop's thread is busy (PROLOG
// rules computing or in sleep/1), and are never handled by default (which
// would end the process with the vehicle at depth). SIGPIPE is ignored: a
// closed terminal or pipe must not end the run before its safe end. A process
// started with SIGINT or SIGHUP ignored (a script's background job, nohup)
// keeps ignoring it; SIGTERM is always taken.
//
// Threads: construct on the main thread before any other thread starts (the
// three signals are blocked in it and in every thread started after); the
// handler runs on the watcher's thread. The destructor stops the watcher and
// leaves the signals blocked: after the run, a late signal changes nothing.
#include <atomic>
#include <functional>
#include <string>
#include <thread>

namespace strata::cli {

class SignalWatcher {
 public:
  // handler(signal number) for each signal that arrives, in order.
  explicit SignalWatcher(std::function<void(int)> handler);
  ~SignalWatcher();
  SignalWatcher(const SignalWatcher&) = delete;
  SignalWatcher& operator=(const SignalWatcher&) = delete;

 private:
  std::function<void(int)> handler_;
  std::atomic<bool> quit_{false};
  std::thread thread_;
};

// "SIGINT", "SIGTERM", "SIGHUP"; "signal N" for others.
std::string signal_name(int signal);

}  // namespace strata::cli
