#include "studio/prolog_thread.h"

#include <csignal>

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

namespace {

// SWI-Prolog, started on this thread, puts its own alternate signal stack
// in place (its C-stack guard's SIGSEGV handler runs there). The thread's
// own, the one it was created with, is put back before the thread ends:
// ASan unmaps the alternate stack it finds at a thread's end, and could
// not unmap SWI's ("failed to deallocate", the studio's PROLOG tests
// under the asan preset).
class AlternateStackKept {
 public:
  AlternateStackKept() { kept_ = ::sigaltstack(nullptr, &original_) == 0; }
  ~AlternateStackKept() {
    if (kept_) ::sigaltstack(&original_, nullptr);
  }
  AlternateStackKept(const AlternateStackKept&) = delete;
  AlternateStackKept& operator=(const AlternateStackKept&) = delete;

 private:
  stack_t original_{};
  bool kept_ = false;
};

}  // namespace

void PrologThread::loop() {
  const AlternateStackKept alternate_stack;
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
