#include "studio/server.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <fstream>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <httplib.h>

#include "coral/verify_report.h"
#include "core/file.h"
#include "studio/assets.h"
#include "studio/file_watcher.h"
#include "studio/http_answers.h"
#include "studio/mission_model.h"
#include "studio/model_patch.h"
#include "studio/prolog_model.h"
#include "studio/replay.h"
#include "studio/run_list.h"
#include "studio/sonar_status.h"
#include "studio/studio_runner.h"

namespace strata::studio {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The largest sonar scan served (a PNG of a few hundred KB in practice).
constexpr std::size_t kMaxScanBytes = 32u << 20;

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

std::string mission_kind(const std::string& path) {
  if (path.ends_with(".coral")) return "coral";
  if (path.ends_with(".pl")) return "prolog";
  return "";
}

}  // namespace

StudioServer::StudioServer(StudioOptions options, EventHub& hub)
    : options_(std::move(options)), hub_(hub), sandbox_(options_.root), server_(std::make_unique<httplib::Server>()) {
  if (!options_.catalogue) options_.catalogue = &tactical::Catalogue::builtin();
  runs_ = options_.runs;
  if (!runs_) {
    own_runner_ = std::make_unique<StudioRunner>(hub_, sandbox_, *options_.catalogue);
    own_runner_->set_sonar_dir(options_.sonar_dir.string());
    runs_ = own_runner_.get();
  }
  const int threads = options_.threads;
  // Debian's library fixes its own pool at 8 threads; an open event stream
  // holds one, so a few tabs would starve every other request.
  server_->new_task_queue = [threads] { return new httplib::ThreadPool(static_cast<std::size_t>(threads)); };
  server_->set_payload_max_length(options_.max_body_bytes);
  // Headers and body go out in two writes: without TCP_NODELAY the body
  // waits for the page's delayed ACK (40 ms a request on a kept-alive
  // connection).
  server_->set_tcp_nodelay(true);
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
  if (own_runner_) own_runner_->abort();  // a run going ends through its safe end
  if (watcher_) watcher_->stop();
  hub_.close();  // every event stream ends
  if (server_) server_->stop();
  if (listener_.joinable()) listener_.join();
}

bool StudioServer::own_host(const std::string& host) const {
  return std::find(own_hosts_.begin(), own_hosts_.end(), lower(host)) != own_hosts_.end();
}

std::optional<std::string> StudioServer::refuse_write(const std::string& relative, const httplib::Request& req,
                                                      int& status) const {
  auto current = sandbox_.read(relative);
  if (!current && current.error().code != core::ErrorCode::Io) {
    status = status_of(current.error());
    return current.error().message;
  }
  const bool exists = current.ok();
  if (!req.has_header("If-Match")) {
    if (!exists) return std::nullopt;  // a new file
    status = 428;
    return fmt::format("'{}' exists: saving over it needs If-Match with the ETag it was read with", relative);
  }
  if (exists && if_match(req.get_header_value("If-Match"), etag_of(current.value()))) return std::nullopt;
  status = 412;
  return exists ? fmt::format(
                      "'{}' changed since it was read (another tab or another program saved it); "
                      "reload it, then make your change again",
                      relative)
                : fmt::format("'{}' is no longer there (it was deleted or moved since it was read)", relative);
}

void StudioServer::routes() {
  httplib::Server& s = *server_;
  const tactical::Catalogue& catalogue = *options_.catalogue;

  // Before any route: the request must be for this studio (Host: against
  // DNS rebinding) and, when it changes anything, come from its own page
  // (Origin: any page the operator visits may POST here, even text/plain
  // without a preflight). GET needs no Origin: a browser does not send one
  // for a same-origin GET, and a GET changes nothing.
  s.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    const std::string host = req.get_header_value("Host");
    if (!own_host(host)) {
      send_error(res, 403, fmt::format("Host '{}' is not this studio's address (http://{})", host, own_hosts_.front()));
      return httplib::Server::HandlerResponse::Handled;
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

  s.Get("/api/files", [this](const httplib::Request&, httplib::Response& res) {
    json missions = json::array();
    for (const auto& path : sandbox_.list({".coral", ".pl"})) {
      missions.push_back({{"path", path}, {"kind", mission_kind(path)}});
    }
    send_json(res, {{"root", sandbox_.root().string()},
                    {"files", sandbox_.list({".coral"})},
                    {"missions", missions},
                    {"logs", sandbox_.list({".jsonl"})}});
  });

  s.Get("/api/mission", [this, &catalogue](const httplib::Request& req, httplib::Response& res) {
    const std::string path = req.get_param_value("path");
    auto real = sandbox_.resolve(path);
    if (!real) return send_path_error(res, real.error());
    if (path.ends_with(".pl")) {
      std::string etag;
      json model = prolog_model(sandbox_, catalogue, path, etag);
      if (!etag.empty()) {
        res.set_header("ETag", etag);
        watcher_->watch(path, etag);
      }
      return send_json(res, model);
    }
    CompiledMission m = compile_mission(sandbox_, path, std::nullopt, catalogue);
    if (!m.etag.empty()) res.set_header("ETag", m.etag);
    // What this page now shows, watched for changes on disk: the file, its
    // layout, and every file its nets come from.
    watcher_->watch(path, m.etag);
    watcher_->watch(path + ".layout.json",
                    m.model["layout_etag"].is_string() ? m.model["layout_etag"].get<std::string>() : "");
    for (const auto& net : m.model["nets"]) {
      const std::string file = net.value("file", "");
      if (file.empty() || file == path) continue;
      auto bytes = sandbox_.read(file);
      watcher_->watch(file, bytes ? etag_of(bytes.value()) : "");
    }
    m.model["kind"] = "coral";
    m.model["read_only"] = false;
    send_json(res, *models_.keep(std::move(m.model)));
  });

  s.Post("/api/check", [this, &catalogue](const httplib::Request& req, httplib::Response& res) {
    auto body = json_body(req, res);
    if (!body) return;
    const std::string path = body->value("path", "");
    auto real = sandbox_.resolve(path, true);
    if (!real) return send_path_error(res, real.error());
    send_json(res, *models_.keep(compile_mission(sandbox_, path, body->value("text", ""), catalogue).model));
  });

  s.Post("/api/edit", [this, &catalogue](const httplib::Request& req, httplib::Response& res) {
    auto body = json_body(req, res);
    if (!body) return;
    const std::string path = body->value("path", "");
    auto real = sandbox_.resolve(path, true);
    if (!real) return send_path_error(res, real.error());
    auto edit = edit_from_json(body->value("op", json()));
    if (!edit) return send_error(res, 400, edit.error().message);
    const std::string before = body->value("text", "");
    const bool deleting =
        edit.value().op == coral::Edit::Op::DeletePlace || edit.value().op == coral::Edit::Op::DeleteTransition;
    std::optional<CompiledMission> old;
    if (deleting) {
      old = compile_mission(sandbox_, path, before, catalogue);
      if (auto why = refuse_delete(old->program, edit.value())) return send_error(res, 400, *why);
    }
    auto text = coral::apply_edit(before, edit.value());
    if (!text) return send_error(res, 400, text.error().message);
    CompiledMission now = compile_mission(sandbox_, path, text.value(), catalogue);
    if (deleting) {
      // Every use went with it, or the delete is refused: an error naming
      // it that the text did not have before means a use was left.
      if (auto left = use_left(old->model["diagnostics"], now.model["diagnostics"], edit.value().name)) {
        return send_error(res, 400, *left);
      }
    }
    // The page names the model it holds (`base`): when it is still kept,
    // and of the text edited, only what changed goes back.
    auto base = models_.find(body->value("base", ""));  // before keeping another: it may be the oldest
    auto kept = models_.keep(std::move(now.model));
    if (base && base->value("text", "") == before) {
      return send_json(res, {{"rev", (*kept)["rev"]}, {"base", (*base)["rev"]}, {"patch", model_patch(*base, *kept)}});
    }
    send_json(res, *kept);
  });

  s.Post("/api/verify", [this, &catalogue](const httplib::Request& req, httplib::Response& res) {
    auto body = json_body(req, res);
    if (!body) return;
    const std::string path = body->value("path", "");
    auto real = sandbox_.resolve(path, true);
    if (!real) return send_path_error(res, real.error());
    std::optional<std::string> text;
    if (body->contains("text") && (*body)["text"].is_string()) text = (*body)["text"].get<std::string>();
    CompiledMission m = compile_mission(sandbox_, path, text, catalogue);
    if (!m.program)
      return send_json(res, {{"error", "the mission does not compile"}, {"diagnostics", m.model["diagnostics"]}}, 422);
    coral::VerifyOptions vo;
    vo.sources = m.sources.get();
    coral::VerifyReport report = coral::verify_program(*m.program, vo);
    // Locations relative to the studio's folder, as everywhere else.
    auto relative = [this](coral::Location& at) { at.file = sandbox_.relative(fs::weakly_canonical(at.file)); };
    for (auto& n : report.nets) {
      relative(n.at);
      for (auto& p : n.properties) relative(p.at);
      for (auto& b : n.bounds) relative(b.at);
    }
    send_json(res, coral::verify_json(report));
  });

  s.Put("/api/file", [this](const httplib::Request& req, httplib::Response& res) {
    const std::string path = req.get_param_value("path");
    if (path.ends_with(".pl")) {
      return send_error(
          res, 403, fmt::format("'{}': PROLOG missions are read-only in the studio; edit them in a text editor", path));
    }
    if (!path.ends_with(".coral"))
      return send_error(res, 403, fmt::format("'{}': only .coral files are written", path));
    std::lock_guard lock(write_mutex_);
    int status = 0;
    if (auto refused = refuse_write(path, req, status)) return send_error(res, status, *refused);
    auto written = sandbox_.write(path, req.body);
    if (!written) return send_error(res, status_of(written.error()), written.error().message);
    const std::string etag = etag_of(req.body);
    res.set_header("ETag", etag);
    send_json(res, {{"ok", true}, {"etag", etag}});
  });

  s.Put("/api/layout", [this](const httplib::Request& req, httplib::Response& res) {
    const std::string path = req.get_param_value("path");
    if (!path.ends_with(".coral"))
      return send_error(res, 403, fmt::format("'{}': a layout belongs to a .coral file", path));
    auto body = json_body(req, res);
    if (!body) return;
    std::lock_guard lock(write_mutex_);
    const std::string layout = path + ".layout.json", bytes = body->dump(1) + "\n";
    int status = 0;
    if (auto refused = refuse_write(layout, req, status)) return send_error(res, status, *refused);
    auto written = sandbox_.write(layout, bytes);
    if (!written) return send_error(res, status_of(written.error()), written.error().message);
    const std::string etag = etag_of(bytes);
    res.set_header("ETag", etag);
    send_json(res, {{"ok", true}, {"etag", etag}});
  });

  s.Get("/api/primitives",
        [&catalogue](const httplib::Request&, httplib::Response& res) { send_json(res, primitives_json(catalogue)); });

  s.Get("/api/replay", [this](const httplib::Request& req, httplib::Response& res) {
    const std::string path = req.get_param_value("path");
    auto text = sandbox_.read(path);
    if (!text) return send_error(res, status_of(text.error()), text.error().message);
    auto replay = replay_from_log(text.value());
    if (!replay) return send_error(res, 422, fmt::format("{}: {}", path, replay.error().message));
    // The log names its mission as the run did (an absolute path for a
    // studio run): the page's name for it is relative to the folder.
    json& mission = replay.value()["mission"];
    if (mission.is_string() && fs::path(mission.get<std::string>()).is_absolute() &&
        sandbox_.lexically_inside(mission.get<std::string>())) {
      mission = sandbox_.relative(fs::path(mission.get<std::string>()).lexically_normal());
    }
    replay.value()["log"] = path;
    send_json(res, replay.value());
  });

  s.Post("/api/run", [this, &catalogue](const httplib::Request& req, httplib::Response& res) {
    auto body = json_body(req, res);
    if (!body) return;
    auto path = string_field(*body, "path", res);
    auto scenario = string_field(*body, "scenario", res);
    if (!path || !scenario) return;
    auto real = sandbox_.resolve(*path);
    if (!real) return send_path_error(res, real.error());
    if (mission_kind(*path).empty()) {
      return send_error(res, 400, fmt::format("'{}' is not a mission (a .coral or .pl file)", *path));
    }
    if (!body->value("speed", json(10.0)).is_number()) return send_error(res, 400, "speed must be a number");
    RunRequest run{real.value(), *path, *scenario, body->value("speed", 10.0), {}};
    if (!(run.speed >= 0.01 && run.speed <= 1000.0)) return send_error(res, 400, "speed must be between 0.01 and 1000");
    // A scenario is a name from the mission's scenarios/, never a path;
    // nominal (or none) is the mission's nominal.toml when it has one, else
    // the built-in one.
    const bool nominal = run.scenario.empty() || run.scenario == "nominal";
    auto file = scenario_file(sandbox_, *path, nominal ? "nominal" : run.scenario);
    if (file) {
      run.scenario_file = file.value();
    } else if (!nominal || file.error().code != core::ErrorCode::Io) {
      return send_error(res, 400, file.error().message);
    } else {
      run.scenario.clear();  // the built-in nominal: no file to look for
    }
    // The run reads the mission again, with its imports and data file: none
    // may leave the folder. (PROLOG rules: the run reads their data file
    // through the sandbox, and refuses one outside.)
    CompiledMission m;
    if (mission_kind(*path) == "coral") m = compile_mission(sandbox_, *path, std::nullopt, catalogue);
    if (m.escaped) {
      return send_error(res, 403, fmt::format("'{}' imports a file outside the studio's folder; not running", *path));
    }
    if (m.program && m.program->mission) {
      const std::string& data = m.program->nets[*m.program->mission].data_file;
      const fs::path rel = fs::path(data).lexically_relative(sandbox_.root());
      auto escapes = [&] {
        if (rel.empty() || *rel.begin() == "..") return true;
        auto found = sandbox_.resolve(rel.generic_string());
        return !found && found.error().code == core::ErrorCode::InvalidInput;  // missing: the run says so
      };
      if (!data.empty() && escapes()) {
        return send_error(res, 403,
                          fmt::format("'{}': its data file is outside the studio's folder; not running", *path));
      }
    }
    auto started = runs_->start(run);
    if (!started) {
      return send_error(res, started.error().code == core::ErrorCode::Overflow ? 409 : 400, started.error().message);
    }
    send_json(res, {{"ok", true}}, 202);
  });

  s.Post("/api/run/stop", [this](const httplib::Request&, httplib::Response& res) {
    runs_->stop();
    send_json(res, {{"ok", true}});
  });
  s.Post("/api/run/abort", [this](const httplib::Request&, httplib::Response& res) {
    runs_->abort();
    send_json(res, {{"ok", true}});
  });

  // The mission logs of studio runs: runs/*.jsonl beside a mission (of one
  // mission, or all), newest first.
  s.Get("/api/runs", [this](const httplib::Request& req, httplib::Response& res) {
    const std::string mission = req.get_param_value("mission");
    if (!mission.empty()) {
      auto real = sandbox_.resolve(mission);
      if (!real) return send_path_error(res, real.error());
    }
    send_json(res, run_list(sandbox_, mission));
  });

  s.Get("/api/events", [this](const httplib::Request&, httplib::Response& res) {
    auto sub = hub_.subscribe();
    const auto heartbeat = options_.heartbeat;
    const auto batch = options_.batch;
    res.set_header("Cache-Control", "no-cache");
    res.set_header("X-Accel-Buffering", "no");
    res.set_chunked_content_provider("text/event-stream",
                                     [sub, heartbeat, batch](std::size_t, httplib::DataSink& sink) {
                                       std::optional<std::string> chunk = sub->next(heartbeat, batch);
                                       if (!chunk) {
                                         sink.done();  // the server is stopping
                                         return true;
                                       }
                                       // A comment when nothing happened: a closed tab is noticed on write.
                                       const std::string text = chunk->empty() ? std::string(": ping\n\n") : *chunk;
                                       return sink.write(text.data(), text.size());
                                     });
  });

  // The newest sonar scan, when a run's Sonar Manager writes one.
  s.Get("/api/sonar",
        [this](const httplib::Request&, httplib::Response& res) { send_json(res, sonar_status(options_.sonar_dir)); });
  s.Get("/api/sonar/latest.png", [this](const httplib::Request&, httplib::Response& res) {
    // A regular file, and bounded: never a FIFO or a device that would hold
    // the worker.
    auto bytes = options_.sonar_dir.empty()
                     ? core::Result<std::string>(core::make_error(core::ErrorCode::Io, "no sonar"))
                     : core::read_regular_file((options_.sonar_dir / "latest.png").string(), kMaxScanBytes);
    if (!bytes) return send_error(res, 404, "no sonar scan yet");
    res.set_header("Cache-Control", "no-store");
    res.set_content(bytes.value(), "image/png");
  });

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
