#pragma once
// What strata needs of the studio's HTTP server without linking its HTTP
// stack (cpp-httplib, and through it OpenSSL, zlib and brotli): the options,
// the runs it starts, and a server loaded when a command serves the studio
// (http_module.h). Every other command starts without those libraries.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "core/result.h"
#include "tactical/catalogue.h"

namespace strata::studio {

class EventHub;

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

struct StudioOptions {
  std::filesystem::path root = ".";
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;                          // 0: any free port
  std::filesystem::path web_root;                  // "": the page compiled into strata
  const tactical::Catalogue* catalogue = nullptr;  // null: the built-in one
  std::size_t max_body_bytes = 4u << 20;           // with Content-Length; a body framed otherwise is refused (411)
  int threads = 48;
  // Event streams open at once, from every client: each holds one of the
  // `threads` workers for as long as it is open. Past it, 503 with
  // Retry-After. The rest of the workers stay for the API.
  int max_streams = 16;
  // Verifications running at once (each may take its memory limit): past
  // it, 429 with Retry-After.
  int max_verifies = 2;
  // A connection a page keeps open between requests is closed after this
  // long idle (cpp-httplib's keep-alive). stop() does not wait for it: it
  // closes every connection at once.
  std::chrono::seconds keep_alive{5};
  std::chrono::milliseconds heartbeat{1000};
  // An event stream looks for news this often and writes all that came in
  // one go: 25 writes a second is plenty for a page, and 20 pages cost a
  // run little.
  std::chrono::milliseconds batch{40};
  // POST /api/run, /api/run/stop and /api/run/abort go here (the caller's
  // StudioRunner, which must outlive the server); null: this studio runs no
  // missions, and those requests are answered 503.
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

// The studio's HTTP server (server.h's StudioServer), as strata holds it.
// Threads: start() returns once the socket is bound and listening on a
// thread of its own; stop() ends every stream, stops the listener and joins
// it; it is safe to call twice, and from the destructor.
class HttpServer {
 public:
  virtual ~HttpServer() = default;
  // Binds and starts listening; the port chosen.
  virtual core::Result<std::uint16_t> start() = 0;
  virtual void stop() = 0;
  virtual std::uint16_t port() const = 0;
  // False when Node.js was missing when strata was built, and only a page
  // saying so is embedded.
  virtual bool page_built() const = 0;
};

}  // namespace strata::studio
