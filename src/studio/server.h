#pragma once
// `strata studio`'s HTTP server (docs/studio.md): the page, the JSON API and
// the Server-Sent Events stream of a run, on 127.0.0.1 by default.
//
// Runs started from the page go through the RunLauncher its caller gives
// (`strata studio`: a StudioRunner, the run library on a thread of its
// own; tests: a recorder); the server never makes one. The run tells the
// EventHub what happens, and the hub feeds every open stream.
//
// Threads: start() returns once the socket is bound and listening on a
// thread of its own; requests are served by a pool of `threads` workers
// (each open event stream holds one). stop() ends every stream, stops the
// listener and joins it; it is safe to call twice, and from the destructor.
#include <sys/socket.h>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <vector>
#include <mutex>
#include <string>
#include <thread>

#include "core/result.h"
#include "studio/event_hub.h"
#include "studio/model_patch.h"
#include "studio/sandbox.h"
#include "studio/studio_http.h"
#include "tactical/catalogue.h"

namespace httplib {
class Server;
struct Request;
struct Response;
}  // namespace httplib

namespace strata::studio {

class FileWatcher;

// Connections waiting to be accepted (listen(2)'s backlog; the kernel caps
// it at net.core.somaxconn, 4096 on Debian 12).
inline constexpr int kListenBacklog = 1024;
// Request headers a request may carry (431 past it).
inline constexpr std::size_t kMaxHeaders = 100;

class StudioServer final : public HttpServer {
 public:
  StudioServer(StudioOptions options, EventHub& hub);
  ~StudioServer() override;
  StudioServer(const StudioServer&) = delete;
  StudioServer& operator=(const StudioServer&) = delete;

  // Binds and starts listening; the port chosen.
  core::Result<std::uint16_t> start() override;
  void stop() override;
  std::uint16_t port() const override { return port_; }
  bool page_built() const override;

 private:
  void routes();                         // the guards (Host, Origin, errors), then the two below, then the page
  void file_routes(httplib::Server& s);  // server_files.cpp
  void run_routes(httplib::Server& s);   // server_runs.cpp
  // The page's assets, precompressed at build time: the variant the
  // request accepts (br, then gzip, else the bytes as built), never
  // compressed here.
  void serve_asset(const httplib::Request& req, httplib::Response& res, const std::string& path);
  // Whether `host` (HOST:PORT) is one of this studio's own addresses.
  bool own_host(const std::string& host) const;
  // Shuts down (shutdown(2), not close) every TCP connection accepted on
  // the listening address: a worker waiting on one for its next request
  // wakes and ends it.
  void shut_down_connections() const;
  // Why writing `relative` with this request's If-Match is refused (status
  // 412, 428, or the sandbox's), or nullopt to go ahead. Under write_mutex_.
  std::optional<std::string> refuse_write(const std::string& relative, const httplib::Request& req, int& status) const;

  StudioOptions options_;
  EventHub& hub_;
  Sandbox sandbox_;
  // Every write of the API (text, layout) holds it: a check of the file's
  // version and the write that follows are one step for other requests.
  std::mutex write_mutex_;
  // The models last answered, for edits answered with a patch.
  ModelCache models_;
  std::unique_ptr<FileWatcher> watcher_;
  RunLauncher* runs_ = nullptr;
  std::unique_ptr<httplib::Server> server_;
  std::thread listener_;
  std::atomic<bool> listener_done_{false};  // listen_after_bind returned
  std::uint16_t port_ = 0;
  std::vector<std::string> own_hosts_;  // set by start(), before the first request
  int listen_fd_ = -1;                  // the listening socket, once made
  sockaddr_storage bound_{};            // its address, once bound (start())
  std::atomic<int> streams_{0};         // event streams open now
  std::atomic<int> verifies_{0};        // verifications running now
};

// Holds one of `count`'s `limit` places while it lives (an event stream, a
// verification); empty when every place was taken.
class Slot {
 public:
  static std::shared_ptr<Slot> take(std::atomic<int>& count, int limit);
  ~Slot() { --count_; }
  Slot(const Slot&) = delete;
  Slot& operator=(const Slot&) = delete;
  explicit Slot(std::atomic<int>& count) : count_(count) {}

 private:
  std::atomic<int>& count_;
};

}  // namespace strata::studio
