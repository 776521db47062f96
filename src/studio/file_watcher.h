#pragma once
// Tells open pages when a file they show changes on disk (another program,
// another tab's save, a `git checkout`): the SSE event
// `file_changed {"path", "etag"}` (etag null when the file is gone or can no
// longer be read inside the folder).
//
// The files watched are those the server gave a page (the mission, its
// imports and its layout, as GET /api/mission serves them). A thread looks
// at them every `period` (lstat: size, modification time, inode — cheap
// for a few hundred files); when one of these moved it reads the file
// through the Sandbox and compares its ETag with the one it knew: only a
// new version is told. At most `max_files` are watched (the least recently
// served is dropped first).
//
// Threads: watch() from any thread (HTTP workers); the polling thread is
// started by start() and ended by stop() (or the destructor), which wakes
// it and joins it at once.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "studio/event_hub.h"
#include "studio/sandbox.h"

namespace strata::studio {

class FileWatcher {
 public:
  FileWatcher(const Sandbox& sandbox, EventHub& hub, std::chrono::milliseconds period, std::size_t max_files = 256);
  ~FileWatcher();
  FileWatcher(const FileWatcher&) = delete;
  FileWatcher& operator=(const FileWatcher&) = delete;

  void start();
  void stop();
  // Watches `relative` (inside the folder), whose version as served is
  // `etag` ("" when it did not exist).
  void watch(const std::string& relative, const std::string& etag);
  std::size_t watched() const;

 private:
  struct Stamp {
    std::int64_t size = -1, mtime_ns = 0, ctime_ns = 0;
    std::uint64_t inode = 0;
    bool operator==(const Stamp&) const = default;
  };
  struct Entry {
    std::string etag;
    Stamp stamp;
    std::uint64_t used = 0;  // when last served, for dropping the oldest
  };
  Stamp stamp_of(const std::string& relative) const;
  void loop();
  void look();

  const Sandbox& sandbox_;
  EventHub& hub_;
  const std::chrono::milliseconds period_;
  const std::size_t max_files_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::map<std::string, Entry> files_;
  std::uint64_t clock_ = 0;
  bool quit_ = false;
  std::thread thread_;
};

}  // namespace strata::studio
