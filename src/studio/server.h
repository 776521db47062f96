#pragma once
// `strata studio`'s HTTP server (docs/studio.md): the page, the JSON API and
// the Server-Sent Events stream of a run, on 127.0.0.1 by default.
//
// Runs started from the page go through a RunLauncher: by default the
// studio's own StudioRunner (the run library on a thread of its own); tests
// may give another. The run tells the EventHub what happens, and the hub
// feeds every open stream.
//
// Threads: start() returns once the socket is bound and listening on a
// thread of its own; requests are served by a pool of `threads` workers
// (each open event stream holds one). stop() ends every stream, stops the
// listener and joins it; it is safe to call twice, and from the destructor.
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
#include "tactical/catalogue.h"

namespace httplib {
class Server;
struct Request;
struct Response;
}  // namespace httplib

namespace strata::studio {

struct RunRequest {
  std::filesystem::path mission;  // resolved, inside the root
  std::string relative;           // as the page named it
  std::string scenario;           // the name asked for; "" nominal
  double speed = 10.0;            // simulated seconds per wall second
  // Set by the server: the scenario's file, checked inside the root; when
  // empty the run takes `scenario` as strata run does (`strata run
  // --studio`, whose scenario comes from its own command line).
  std::filesystem::path scenario_file = {};
};

// Starts and stops the runs the page asks for. Threads: any (HTTP workers).
class RunLauncher {
 public:
  virtual ~RunLauncher() = default;
  // Starts the run (on another thread) or says why not (InvalidInput: 400;
  // Overflow: 409, a run is going).
  virtual core::Result<void> start(const RunRequest& request) = 0;
  // The page's Abort: the run going, if any, ends through its safe end
  // (surface, then done); its outcome is aborted, stopped_by "studio".
  virtual void abort() = 0;
  // The page's Stop, a hard stop: the run going, if any, ends now, without
  // surfacing the vehicle or sending it done (run::StopMode::Hard).
  virtual void stop() = 0;
};

class StudioRunner;
class FileWatcher;

struct StudioOptions {
  std::filesystem::path root = ".";
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;                          // 0: any free port
  std::filesystem::path web_root;                  // "": the page compiled into strata
  const tactical::Catalogue* catalogue = nullptr;  // null: the built-in one
  std::size_t max_body_bytes = 4u << 20;
  int threads = 48;
  std::chrono::milliseconds heartbeat{1000};
  // An event stream looks for news this often and writes all that came in
  // one go: 25 writes a second is plenty for a page, and 20 pages cost a
  // run little.
  std::chrono::milliseconds batch{40};
  // POST /api/run and /api/run/stop go here; null: the studio's own
  // StudioRunner (which must then outlive nothing: the server owns it).
  RunLauncher* runs = nullptr;
  // Where the Sonar Manager of a run writes its scans (latest.png and
  // sonar.jsonl): GET /api/sonar says what is there, and
  // GET /api/sonar/latest.png serves the newest scan. "": no sonar.
  std::filesystem::path sonar_dir;
  // How often the files open pages show are looked at for changes on disk
  // (FileWatcher; file_changed events).
  std::chrono::milliseconds watch_period{500};
  // A line for each request answered ("GET /api/files 200"), from the
  // server's threads (`strata studio -v`); null: none.
  std::function<void(const std::string&)> request_log;
};

class StudioServer {
 public:
  StudioServer(StudioOptions options, EventHub& hub);
  ~StudioServer();
  StudioServer(const StudioServer&) = delete;
  StudioServer& operator=(const StudioServer&) = delete;

  // Binds and starts listening; the port chosen.
  core::Result<std::uint16_t> start();
  void stop();
  std::uint16_t port() const { return port_; }

 private:
  void routes();
  // The page's assets, precompressed at build time: the variant the
  // request accepts (br, then gzip, else the bytes as built), never
  // compressed here.
  void serve_asset(const httplib::Request& req, httplib::Response& res, const std::string& path);
  // Whether `host` (HOST:PORT) is one of this studio's own addresses.
  bool own_host(const std::string& host) const;
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
  std::unique_ptr<StudioRunner> own_runner_;  // when options_.runs is null
  std::unique_ptr<FileWatcher> watcher_;
  RunLauncher* runs_ = nullptr;
  std::unique_ptr<httplib::Server> server_;
  std::thread listener_;
  std::uint16_t port_ = 0;
  std::vector<std::string> own_hosts_;  // set by start(), before the first request
};

}  // namespace strata::studio
