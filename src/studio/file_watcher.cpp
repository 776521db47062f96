#include "studio/file_watcher.h"

#include <sys/stat.h>

#include <vector>

#include "studio/mission_model.h"

namespace strata::studio {

FileWatcher::FileWatcher(const Sandbox& sandbox, EventHub& hub, std::chrono::milliseconds period, std::size_t max_files)
    : sandbox_(sandbox), hub_(hub), period_(period), max_files_(max_files) {}

FileWatcher::~FileWatcher() { stop(); }

void FileWatcher::start() {
  std::lock_guard lock(mutex_);
  if (thread_.joinable()) return;
  quit_ = false;
  thread_ = std::thread([this] { loop(); });
}

void FileWatcher::stop() {
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

FileWatcher::Stamp FileWatcher::stamp_of(const std::string& relative) const {
  // The name as it is in the folder, not followed: what is there now. A
  // link is stamped as a link; reading it (through the sandbox) decides.
  struct stat st {};
  Stamp s;
  if (::lstat((sandbox_.root() / relative).c_str(), &st) != 0) return s;
  s.size = st.st_size;
  s.mtime_ns = std::int64_t{st.st_mtim.tv_sec} * 1'000'000'000 + st.st_mtim.tv_nsec;
  s.ctime_ns = std::int64_t{st.st_ctim.tv_sec} * 1'000'000'000 + st.st_ctim.tv_nsec;
  s.inode = st.st_ino;
  return s;
}

void FileWatcher::watch(const std::string& relative, const std::string& etag) {
  const Stamp stamp = stamp_of(relative);
  std::lock_guard lock(mutex_);
  Entry& e = files_[relative];
  e.etag = etag;
  e.stamp = stamp;
  e.used = ++clock_;
  while (files_.size() > max_files_) {
    auto oldest = files_.begin();
    for (auto it = files_.begin(); it != files_.end(); ++it) {
      if (it->second.used < oldest->second.used) oldest = it;
    }
    files_.erase(oldest);
  }
}

std::size_t FileWatcher::watched() const {
  std::lock_guard lock(mutex_);
  return files_.size();
}

void FileWatcher::loop() {
  std::unique_lock lock(mutex_);
  while (!quit_) {
    wake_.wait_for(lock, period_, [&] { return quit_; });
    if (quit_) return;
    lock.unlock();
    look();
    lock.lock();
  }
}

void FileWatcher::look() {
  std::vector<std::pair<std::string, Stamp>> moved;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [path, e] : files_) {
      if (Stamp now = stamp_of(path); !(now == e.stamp)) moved.emplace_back(path, now);
    }
  }
  for (const auto& [path, stamp] : moved) {
    auto bytes = sandbox_.read(path);
    const std::string etag = bytes ? etag_of(bytes.value()) : std::string();
    bool changed = false;
    {
      std::lock_guard lock(mutex_);
      auto it = files_.find(path);
      if (it == files_.end()) continue;  // dropped meanwhile
      it->second.stamp = stamp;
      if (it->second.etag != etag) {
        it->second.etag = etag;
        changed = true;
      }
    }
    if (changed) {
      hub_.publish("file_changed",
                   {{"path", path}, {"etag", etag.empty() ? nlohmann::json(nullptr) : nlohmann::json(etag)}});
    }
  }
}

}  // namespace strata::studio
