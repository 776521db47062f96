#pragma once
// SWI-Prolog runs on one thread per process (prolog/engine.h): every
// PROLOG call the studio makes — checking rules for the page, running a
// .pl mission — goes to this one thread, one job at a time.
//
// Threads: try_run() and run() from any thread. A job that runs for long (a
// PROLOG mission) keeps the thread busy: try_run() then says so at once
// instead of waiting, so a page's request never waits for a run.
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace strata::studio {

class PrologThread {
 public:
  // The process's one.
  static PrologThread& instance();
  ~PrologThread();

  // Runs `job` on the thread and waits for it, unless the thread is busy
  // with another job or SWI-Prolog was started on another thread of this
  // process (`strata run --studio` runs its rules on the main thread):
  // then returns false without running it.
  bool try_run(const std::function<void()>& job);
  // Queues `job` and returns at once; false as try_run() (busy or SWI on
  // another thread): not queued.
  bool post(std::function<void()> job);

 private:
  PrologThread();
  bool usable_locked() const;
  void loop();

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::function<void()> job_;
  bool busy_ = false;  // a job taken and not finished, or queued
  bool ran_ = false;   // a job ran here (SWI, if started, was started here)
  bool quit_ = false;
  std::thread thread_;
};

}  // namespace strata::studio
