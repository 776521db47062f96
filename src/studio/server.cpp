#include "studio/server.h"

#include <fstream>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <httplib.h>

#include "coral/verify_report.h"
#include "sonar/output.h"
#include "studio/assets.h"
#include "studio/mission_model.h"
#include "studio/replay.h"
#include "studio/studio_runner.h"

namespace strata::studio {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

void send_json(httplib::Response& res, const json& body, int status = 200) {
  res.status = status;
  res.set_content(body.dump(-1, ' ', false, json::error_handler_t::replace), "application/json");
}

void send_error(httplib::Response& res, int status, const std::string& message) {
  send_json(res, {{"error", message}}, status);
}

// 403 for a path that leaves the folder, 404 for one that is not there.
void send_path_error(httplib::Response& res, const core::Error& e) {
  send_error(res, e.code == core::ErrorCode::Io ? 404 : 403, e.message);
}

// The status of a failed Sandbox::write() or read().
int status_of(const core::Error& e) {
  switch (e.code) {
    case core::ErrorCode::InvalidInput: return 403;
    case core::ErrorCode::Io: return 404;
    case core::ErrorCode::Overflow: return 413;
    default: return 500;
  }
}

const char* mime_of(const std::string& path) {
  if (path.ends_with(".html")) return "text/html; charset=utf-8";
  if (path.ends_with(".js")) return "text/javascript; charset=utf-8";
  if (path.ends_with(".css")) return "text/css; charset=utf-8";
  if (path.ends_with(".svg")) return "image/svg+xml";
  if (path.ends_with(".png")) return "image/png";
  if (path.ends_with(".json")) return "application/json";
  return "application/octet-stream";
}

// The body as a JSON object, or a 400 already sent.
std::optional<json> json_body(const httplib::Request& req, httplib::Response& res) {
  json j = json::parse(req.body, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    send_error(res, 400, "the body is not a JSON object");
    return std::nullopt;
  }
  return j;
}

}  // namespace

json sonar_status(const std::filesystem::path& dir) {
  json out = {{"dir", !dir.empty()}, {"latest", nullptr}, {"frame", nullptr}};
  if (dir.empty()) return out;
  std::error_code ec;
  const fs::path png = dir / "latest.png";
  const auto size = fs::file_size(png, ec);
  if (!ec) {
    const auto mtime = fs::last_write_time(png, ec);
    const auto ms = ec ? 0 : std::chrono::duration_cast<std::chrono::milliseconds>(mtime.time_since_epoch()).count();
    out["latest"] = {{"bytes", size}, {"mtime_ms", ms}};
  }
  // The newest line of sonar.jsonl: the end summary once there is one, else
  // the newest frame's.
  const sonar::LastLines last = sonar::read_last_lines(dir);
  json line = json::parse(last.end.empty() ? last.frame : last.end, nullptr, false);
  if (!line.is_discarded()) out["frame"] = std::move(line);
  return out;
}

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
  routes();
}

StudioServer::~StudioServer() { stop(); }

core::Result<std::uint16_t> StudioServer::start() {
  const int port = options_.port == 0 ? server_->bind_to_any_port(options_.host)
                                      : (server_->bind_to_port(options_.host, options_.port) ? options_.port : -1);
  if (port <= 0) {
    return core::Error{core::ErrorCode::Io,
                       fmt::format("cannot listen on {}:{}", options_.host, options_.port == 0 ? std::string("any port")
                                                                                          : std::to_string(options_.port))};
  }
  port_ = static_cast<std::uint16_t>(port);
  listener_ = std::thread([this] { server_->listen_after_bind(); });
  return port_;
}

void StudioServer::stop() {
  if (own_runner_) own_runner_->stop();  // a run going ends through its safe end
  hub_.close();  // every event stream ends
  if (server_) server_->stop();
  if (listener_.joinable()) listener_.join();
}

void StudioServer::routes() {
  httplib::Server& s = *server_;
  const tactical::Catalogue& catalogue = *options_.catalogue;

  s.Get("/api/files", [this](const httplib::Request&, httplib::Response& res) {
    send_json(res, {{"root", sandbox_.root().string()},
                    {"files", sandbox_.list({".coral"})},
                    {"logs", sandbox_.list({".jsonl"})}});
  });

  s.Get("/api/mission", [this, &catalogue](const httplib::Request& req, httplib::Response& res) {
    const std::string path = req.get_param_value("path");
    auto real = sandbox_.resolve(path);
    if (!real) return send_path_error(res, real.error());
    send_json(res, compile_mission(sandbox_, path, std::nullopt, catalogue).model);
  });

  s.Post("/api/check", [this, &catalogue](const httplib::Request& req, httplib::Response& res) {
    auto body = json_body(req, res);
    if (!body) return;
    const std::string path = body->value("path", "");
    auto real = sandbox_.resolve(path, true);
    if (!real) return send_path_error(res, real.error());
    send_json(res, compile_mission(sandbox_, path, body->value("text", ""), catalogue).model);
  });

  s.Post("/api/edit", [this, &catalogue](const httplib::Request& req, httplib::Response& res) {
    auto body = json_body(req, res);
    if (!body) return;
    const std::string path = body->value("path", "");
    auto real = sandbox_.resolve(path, true);
    if (!real) return send_path_error(res, real.error());
    auto edit = edit_from_json(body->value("op", json()));
    if (!edit) return send_error(res, 400, edit.error().message);
    auto text = coral::apply_edit(body->value("text", ""), edit.value());
    if (!text) return send_error(res, 400, text.error().message);
    send_json(res, compile_mission(sandbox_, path, text.value(), catalogue).model);
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
    if (!m.program) return send_json(res, {{"error", "the mission does not compile"}, {"diagnostics", m.model["diagnostics"]}}, 422);
    send_json(res, coral::verify_json(coral::verify_program(*m.program)));
  });

  s.Put("/api/file", [this](const httplib::Request& req, httplib::Response& res) {
    const std::string path = req.get_param_value("path");
    if (!path.ends_with(".coral")) return send_error(res, 403, fmt::format("'{}': only .coral files are written", path));
    std::lock_guard lock(write_mutex_);
    auto written = sandbox_.write(path, req.body);
    if (!written) return send_error(res, status_of(written.error()), written.error().message);
    send_json(res, {{"ok", true}});
  });

  s.Put("/api/layout", [this](const httplib::Request& req, httplib::Response& res) {
    const std::string path = req.get_param_value("path");
    if (!path.ends_with(".coral")) return send_error(res, 403, fmt::format("'{}': a layout belongs to a .coral file", path));
    auto body = json_body(req, res);
    if (!body) return;
    std::lock_guard lock(write_mutex_);
    auto written = sandbox_.write(path + ".layout.json", body->dump(1) + "\n");
    if (!written) return send_error(res, status_of(written.error()), written.error().message);
    send_json(res, {{"ok", true}});
  });

  s.Get("/api/primitives", [&catalogue](const httplib::Request&, httplib::Response& res) {
    send_json(res, primitives_json(catalogue));
  });

  s.Get("/api/replay", [this](const httplib::Request& req, httplib::Response& res) {
    const std::string path = req.get_param_value("path");
    auto real = sandbox_.resolve(path);
    if (!real) return send_path_error(res, real.error());
    auto text = read_whole_file(real.value());
    if (!text) return send_error(res, 404, fmt::format("cannot read '{}'", path));
    auto replay = replay_from_log(*text);
    if (!replay) return send_error(res, 422, fmt::format("{}: {}", path, replay.error().message));
    send_json(res, replay.value());
  });

  s.Post("/api/run", [this](const httplib::Request& req, httplib::Response& res) {
    auto body = json_body(req, res);
    if (!body) return;
    const std::string path = body->value("path", "");
    auto real = sandbox_.resolve(path);
    if (!real) return send_path_error(res, real.error());
    RunRequest run{real.value(), path, body->value("scenario", ""), body->value("speed", 10.0)};
    if (!(run.speed >= 0.01 && run.speed <= 1000.0)) return send_error(res, 400, "speed must be between 0.01 and 1000");
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

  s.Get("/api/events", [this](const httplib::Request&, httplib::Response& res) {
    auto sub = hub_.subscribe();
    const auto heartbeat = options_.heartbeat;
    const auto batch = options_.batch;
    res.set_header("Cache-Control", "no-cache");
    res.set_header("X-Accel-Buffering", "no");
    res.set_chunked_content_provider("text/event-stream", [sub, heartbeat, batch](std::size_t, httplib::DataSink& sink) {
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
  s.Get("/api/sonar", [this](const httplib::Request&, httplib::Response& res) {
    send_json(res, sonar_status(options_.sonar_dir));
  });
  s.Get("/api/sonar/latest.png", [this](const httplib::Request&, httplib::Response& res) {
    auto bytes = options_.sonar_dir.empty() ? std::nullopt : read_whole_file(options_.sonar_dir / "latest.png");
    if (!bytes) return send_error(res, 404, "no sonar scan yet");
    res.set_header("Cache-Control", "no-store");
    res.set_content(*bytes, "image/png");
  });

  // The page: from --web-root, or compiled in.
  s.Get(R"(/(.*))", [this](const httplib::Request& req, httplib::Response& res) {
    std::string path = req.matches[1];
    if (path.empty()) path = "index.html";
    if (path.starts_with("api/")) return send_error(res, 404, "no such API");
    if (!options_.web_root.empty()) {
      Sandbox web(options_.web_root);
      auto real = web.resolve(path);
      if (!real) return send_error(res, 404, real.error().message);
      auto text = read_whole_file(real.value());
      if (!text) return send_error(res, 404, "not found");
      return res.set_content(*text, mime_of(path));
    }
    auto asset = embedded_asset(path);
    if (!asset) return send_error(res, 404, fmt::format("'{}' is not part of the page", path));
    res.set_content(std::string(asset->data), mime_of(path));
  });
}

}  // namespace strata::studio
