#include "studio/server.h"

#include <arpa/inet.h>
#include <netinet/in.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <filesystem>
#include <map>
#include <system_error>
#include <thread>

#include <fmt/format.h>
#include <httplib.h>
#include <sys/socket.h>

#include "studio/assets.h"
#include "studio/file_watcher.h"
#include "studio/http_answers.h"

namespace strata::studio {
namespace {

// Every API path and the methods it answers: another method is 405.
const std::map<std::string, std::string, std::less<>>& api_methods() {
  static const std::map<std::string, std::string, std::less<>> methods = {
      {"/api/files", "GET"},   {"/api/mission", "GET"},   {"/api/check", "POST"},     {"/api/edit", "POST"},
      {"/api/verify", "POST"}, {"/api/file", "PUT"},      {"/api/layout", "PUT"},     {"/api/primitives", "GET"},
      {"/api/run", "POST"},    {"/api/run/stop", "POST"}, {"/api/run/abort", "POST"}, {"/api/runs", "GET"},
      {"/api/events", "GET"},  {"/api/replay", "GET"},    {"/api/sonar", "GET"},      {"/api/sonar/latest.png", "GET"}};
  return methods;
}

// A known API path asked with a method it does not answer: 405 with Allow.
bool method_not_allowed(const httplib::Request& req, httplib::Response& res) {
  auto it = api_methods().find(req.path);
  if (it == api_methods().end()) return false;
  res.set_header("Allow", it->second == "GET" ? "GET, HEAD" : it->second);
  send_error(res, 405, fmt::format("{} {}: method not allowed; it answers {}", req.method, req.path, it->second));
  return true;
}

// Why a request for the API is not from this studio's own page, or "". A
// browser says where a request comes from (Sec-Fetch-Site): "same-origin"
// from the page, "none" from the address bar. A page on another port of
// this machine is "same-site", another host "cross-site": either may embed
// an event stream (an iframe holds a worker for ever) or read nothing but
// still make the studio work, so both are refused, whatever the method.
std::string cross_site(const httplib::Request& req) {
  if (!req.has_header("Sec-Fetch-Site")) return "";
  const std::string site = req.get_header_value("Sec-Fetch-Site");
  if (site == "same-origin" || site == "none") return "";
  return fmt::format("{} {}: a request from another site (Sec-Fetch-Site: {}); only this studio's own page may ask",
                     req.method, req.path, site);
}

}  // namespace

std::shared_ptr<Slot> Slot::take(std::atomic<int>& count, int limit) {
  if (++count > limit) {
    --count;
    return nullptr;
  }
  return std::make_shared<Slot>(count);
}

StudioServer::StudioServer(StudioOptions options, EventHub& hub)
    : options_(std::move(options)), hub_(hub), sandbox_(options_.root), server_(std::make_unique<httplib::Server>()) {
  if (!options_.catalogue) options_.catalogue = &tactical::Catalogue::builtin();
  runs_ = options_.runs;
  const int threads = options_.threads;
  // Debian's library fixes its own pool at 8 threads; an open event stream
  // holds one, so a few tabs would starve every other request.
  server_->new_task_queue = [threads] { return new httplib::ThreadPool(static_cast<std::size_t>(threads)); };
  server_->set_payload_max_length(options_.max_body_bytes);
  // The library listens with a backlog of 5: a burst of connections
  // overflows it, and each dropped SYN is retried by the client after 1, 3,
  // 7, 15... seconds (a GET of the file list took a minute beside 1,000
  // others). The socket is kept here and listened on again with a deep
  // backlog once bound.
  server_->set_socket_options([this](int sock) {
    httplib::default_socket_options(sock);
    listen_fd_ = sock;
  });
  // Headers and body go out in two writes: without TCP_NODELAY the body
  // waits for the page's delayed ACK (40 ms a request on a kept-alive
  // connection).
  server_->set_tcp_nodelay(true);
  server_->set_keep_alive_timeout(static_cast<time_t>(options_.keep_alive.count()));
  if (options_.request_log) {
    server_->set_logger([log = options_.request_log](const httplib::Request& req, const httplib::Response& res) {
      log(req.method + " " + req.path + " " + std::to_string(res.status));
    });
  }
  watcher_ = std::make_unique<FileWatcher>(sandbox_, hub_, options_.watch_period);
  routes();
}

StudioServer::~StudioServer() { stop(); }

bool StudioServer::page_built() const { return studio::page_built(); }

core::Result<std::uint16_t> StudioServer::start() {
  const int port = options_.port == 0 ? server_->bind_to_any_port(options_.host)
                                      : (server_->bind_to_port(options_.host, options_.port) ? options_.port : -1);
  if (port <= 0) {
    return core::Error{core::ErrorCode::Io,
                       fmt::format("cannot listen on {}:{}", options_.host,
                                   options_.port == 0 ? std::string("any port") : std::to_string(options_.port))};
  }
  port_ = static_cast<std::uint16_t>(port);
  if (listen_fd_ >= 0) {
    ::listen(listen_fd_, kListenBacklog);
    socklen_t length = sizeof bound_;
    if (::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&bound_), &length) != 0) bound_ = {};
  }
  // The addresses a request may name (Host) and come from (Origin): the one
  // printed first, then the loopback forms a browser may be given.
  own_hosts_ = {lower(fmt::format("{}:{}", options_.host, port_))};
  for (const char* h : {"127.0.0.1", "localhost"}) {
    const std::string form = fmt::format("{}:{}", h, port_);
    if (form != own_hosts_.front()) own_hosts_.push_back(form);
  }
  listener_ = std::thread([this] {
    server_->listen_after_bind();
    listener_done_ = true;
  });
  // Returns once the server is in its accept loop: cpp-httplib's stop()
  // does nothing before that, so a stop() right after start() (Ctrl-C as
  // the URL is printed) left the listener running and stop() joining it
  // for ever.
  for (int i = 0; i < 5000 && !server_->is_running() && !listener_done_; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (!server_->is_running()) {
    server_->stop();
    if (listener_done_ && listener_.joinable()) listener_.join();
    return core::Error{core::ErrorCode::Io,
                       fmt::format("cannot listen on {}:{}: the server did not start", options_.host, port_)};
  }
  watcher_->start();
  return port_;
}

void StudioServer::stop() {
  if (watcher_) watcher_->stop();
  hub_.close();  // every event stream ends
  if (server_) server_->stop();
  // The library's stop() closes the listening socket, then joins its
  // workers; a worker holding a kept-alive connection ends only when the
  // client sends again or its keep-alive runs out (5 s: Ctrl-C with a tab
  // open took 5 s). Every connection is shut down now instead.
  if (port_ != 0 && listener_.joinable()) shut_down_connections();
  if (listener_.joinable()) listener_.join();
}

namespace {

// The port of an IPv4 or IPv6 address; 0 for another family.
std::uint16_t port_of(const sockaddr_storage& a) {
  if (a.ss_family == AF_INET) return ntohs(reinterpret_cast<const sockaddr_in*>(&a)->sin_port);
  if (a.ss_family == AF_INET6) return ntohs(reinterpret_cast<const sockaddr_in6*>(&a)->sin6_port);
  return 0;
}

// Whether `local`, an accepted connection's own address, is on the
// listening address `bound`: the same port, and the same address unless
// the studio listens on every address (0.0.0.0 or ::).
bool on_listening_address(const sockaddr_storage& local, const sockaddr_storage& bound) {
  if (local.ss_family != bound.ss_family || port_of(local) != port_of(bound) || port_of(bound) == 0) return false;
  if (bound.ss_family == AF_INET) {
    const auto& b = reinterpret_cast<const sockaddr_in&>(bound).sin_addr;
    const auto& l = reinterpret_cast<const sockaddr_in&>(local).sin_addr;
    return b.s_addr == htonl(INADDR_ANY) || b.s_addr == l.s_addr;
  }
  const auto& b = reinterpret_cast<const sockaddr_in6&>(bound).sin6_addr;
  const auto& l = reinterpret_cast<const sockaddr_in6&>(local).sin6_addr;
  return IN6_IS_ADDR_UNSPECIFIED(&b) || IN6_ARE_ADDR_EQUAL(&b, &l);
}

}  // namespace

void StudioServer::shut_down_connections() const {
  // A worker may close a connection while this looks: its descriptor's
  // number can be reused at once, so each is checked just before its
  // shutdown (a stream socket on the listening address, with a peer);
  // nothing else in the process has such a socket once the listener is
  // closed.
  std::error_code ec;
  std::filesystem::directory_iterator it("/proc/self/fd", ec);
  for (; !ec && it != std::filesystem::directory_iterator(); it.increment(ec)) {
    int fd = -1;
    const std::string name = it->path().filename().string();
    const auto [end, why] = std::from_chars(name.data(), name.data() + name.size(), fd);
    if (why != std::errc{} || end != name.data() + name.size() || fd < 0) continue;
    int type = 0;
    socklen_t length = sizeof type;
    if (::getsockopt(fd, SOL_SOCKET, SO_TYPE, &type, &length) != 0 || type != SOCK_STREAM) continue;
    sockaddr_storage local{};
    length = sizeof local;
    if (::getsockname(fd, reinterpret_cast<sockaddr*>(&local), &length) != 0 || !on_listening_address(local, bound_)) {
      continue;
    }
    sockaddr_storage peer{};
    length = sizeof peer;
    if (::getpeername(fd, reinterpret_cast<sockaddr*>(&peer), &length) == 0) ::shutdown(fd, SHUT_RDWR);
  }
}

bool StudioServer::own_host(const std::string& host) const {
  return std::find(own_hosts_.begin(), own_hosts_.end(), lower(host)) != own_hosts_.end();
}

void StudioServer::routes() {
  httplib::Server& s = *server_;

  // Before any route: the request must be for this studio (Host: against
  // DNS rebinding) and, when it changes anything, come from its own page
  // (Origin: any page the operator visits may POST here, even text/plain
  // without a preflight). GET needs no Origin: a browser does not send one
  // for a same-origin GET, and a GET changes nothing.
  s.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    // A browser sends a dozen or two headers. (The library has read them all
    // by now: this refuses the request, it does not bound that read.)
    std::size_t headers = req.headers.size();
    for (const char* own : {"REMOTE_ADDR", "REMOTE_PORT", "LOCAL_ADDR", "LOCAL_PORT"}) {
      headers -= req.headers.count(own);  // the library's, not the client's
    }
    if (headers > kMaxHeaders) {
      res.set_header("Connection", "close");
      send_error(res, 431, fmt::format("{} request headers; at most {}", headers, kMaxHeaders));
      return httplib::Server::HandlerResponse::Handled;
    }
    const std::string host = req.get_header_value("Host");
    if (const std::size_t hosts = req.get_header_value_count("Host"); hosts != 1) {
      send_error(res, 400,
                 hosts == 0
                     ? fmt::format("a request names this studio's address in Host: http://{}", own_hosts_.front())
                     : fmt::format("a request names its Host once ({} given)", hosts));
      return httplib::Server::HandlerResponse::Handled;
    }
    if (!own_host(host)) {
      send_error(res, 403, fmt::format("Host '{}' is not this studio's address (http://{})", host, own_hosts_.front()));
      return httplib::Server::HandlerResponse::Handled;
    }
    // A body comes with its length: the library reads a chunked one whole,
    // past max_body_bytes, before any handler. Refused here, before it is
    // read; the connection closes (what follows is that body).
    if (req.has_header("Transfer-Encoding")) {
      res.set_header("Connection", "close");
      send_error(res, 411,
                 fmt::format("a request body needs Content-Length (Transfer-Encoding: {} is refused); at most {} bytes",
                             req.get_header_value("Transfer-Encoding"), options_.max_body_bytes));
      return httplib::Server::HandlerResponse::Handled;
    }
    if (req.path.starts_with("/api/")) {
      if (std::string why = cross_site(req); !why.empty()) {
        send_error(res, 403, why);
        return httplib::Server::HandlerResponse::Handled;
      }
      // An Origin, when a GET has one, is this studio's too.
      const std::string origin = req.get_header_value("Origin");
      if (!origin.empty() && (!origin.starts_with("http://") || !own_host(origin.substr(7)))) {
        send_error(res, 403, fmt::format("Origin '{}' is not this studio (http://{})", origin, own_hosts_.front()));
        return httplib::Server::HandlerResponse::Handled;
      }
    }
    if (req.method != "GET" && req.method != "HEAD") {
      const std::string origin = req.get_header_value("Origin");
      if (!origin.starts_with("http://") || !own_host(origin.substr(7))) {
        send_error(res, 403,
                   origin.empty()
                       ? fmt::format("a {} needs an Origin header: this studio's own, http://{}", req.method,
                                     own_hosts_.front())
                       : fmt::format("Origin '{}' is not this studio (http://{})", origin, own_hosts_.front()));
        return httplib::Server::HandlerResponse::Handled;
      }
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  // The library's own errors (no route, a body too large, a bad request)
  // as JSON too.
  s.set_error_handler(httplib::Server::HandlerWithResponse([](const httplib::Request& req, httplib::Response& res) {
    // Answered by a handler already (every handler's error is JSON).
    if (!res.body.empty() || res.has_header("Content-Type")) return httplib::Server::HandlerResponse::Unhandled;
    if (res.status == 404 && method_not_allowed(req, res)) return httplib::Server::HandlerResponse::Handled;
    if (res.status == 404 && req.path.starts_with("/api/")) {
      send_error(res, 404, fmt::format("{} {}: no such API", req.method, req.path));
    } else {
      send_error(res, res.status,
                 res.status == 413 ? "the request body is too large" : fmt::format("HTTP {}", res.status));
    }
    return httplib::Server::HandlerResponse::Handled;
  }));
  s.set_exception_handler([](const httplib::Request&, httplib::Response& res, const std::exception_ptr& ep) {
    // A field of the wrong type in a JSON body is the client's mistake.
    std::string what = "internal error";
    int status = 500;
    try {
      if (ep) std::rethrow_exception(ep);
    } catch (const nlohmann::json::exception& e) {
      status = 400;
      what = fmt::format("the body: {}", e.what());
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {}
    send_error(res, status, what);
  });

  file_routes(s);
  run_routes(s);

  // The page: from --web-root, or compiled in.
  s.Get(R"(/(.*))", [this](const httplib::Request& req, httplib::Response& res) {
    std::string path = req.matches[1];
    if (path.empty()) path = "index.html";
    if (path.starts_with("api/") || path == "api") {
      if (method_not_allowed(req, res)) return;
      return send_error(res, 404, fmt::format("{} {}: no such API", req.method, req.path));
    }
    if (!options_.web_root.empty()) {
      // Through the sandbox's read: inside the folder, a regular file (a
      // FIFO planted there must not hold a worker), bounded.
      Sandbox web(options_.web_root);
      auto text = web.read(path);
      if (!text) return send_error(res, 404, text.error().message);
      return send_bytes(res, std::move(text.value()), mime_of(path));
    }
    serve_asset(req, res, path);
  });
}

void StudioServer::serve_asset(const httplib::Request& req, httplib::Response& res, const std::string& path) {
  auto asset = embedded_asset(path);
  if (!asset) return send_error(res, 404, fmt::format("'{}' is not part of the page", path));
  res.set_header("Vary", "Accept-Encoding");
  const std::string accept = req.get_header_value("Accept-Encoding");
  if (!asset->brotli.empty() && accepts(accept, "br")) {
    res.set_header("Content-Encoding", "br");
    return send_bytes_view(res, asset->brotli, mime_of(path));
  }
  if (!asset->gzip.empty() && accepts(accept, "gzip")) {
    res.set_header("Content-Encoding", "gzip");
    return send_bytes_view(res, asset->gzip, mime_of(path));
  }
  send_bytes_view(res, asset->data, mime_of(path));
}

}  // namespace strata::studio