#include "studio/prolog_thread.h"

#include "prolog/engine.h"

namespace strata::studio {

PrologThread& PrologThread::instance() {
  static PrologThread thread;
  return thread;
}

PrologThread::PrologThread() : thread_([this] { loop(); }) {}

PrologThread::~PrologThread() {
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

bool PrologThread::usable_locked() const { return !busy_ && (ran_ || !prolog::initialised()); }

bool PrologThread::post(std::function<void()> job) {
  {
    std::lock_guard lock(mutex_);
    if (!usable_locked()) return false;
    busy_ = true;
    job_ = std::move(job);
  }
  wake_.notify_all();
  return true;
}

bool PrologThread::try_run(const std::function<void()>& job) {
  bool finished = false;
  auto wrapped = [&] {
    job();
    std::lock_guard lock(mutex_);
    finished = true;
  };
  if (!post(wrapped)) return false;
  std::unique_lock lock(mutex_);
  done_.wait(lock, [&] { return finished; });
  return true;
}

void PrologThread::loop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return quit_ || job_; });
    if (!job_) return;  // quitting with nothing queued
    auto job = std::move(job_);
    job_ = nullptr;
    ran_ = true;
    lock.unlock();
    job();
    lock.lock();
    busy_ = false;
    done_.notify_all();
  }
}

}  // namespace strata::studio
