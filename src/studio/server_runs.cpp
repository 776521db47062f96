#include "studio/server.h"

// The studio's run API: start, stop and abort a run, the runs list, a
// run's replay, the event stream, and the sonar's newest scan.

#include <filesystem>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <httplib.h>

#include "core/file.h"
#include "studio/http_answers.h"
#include "studio/mission_model.h"
#include "studio/replay.h"
#include "studio/run_list.h"
#include "studio/sonar_status.h"

namespace strata::studio {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The largest sonar scan served (a PNG of a few hundred KB in practice).
constexpr std::size_t kMaxScanBytes = 32u << 20;

}  // namespace

void StudioServer::run_routes(httplib::Server& s) {
  const tactical::Catalogue& catalogue = *options_.catalogue;

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
    if (!runs_) return send_error(res, 503, "this studio runs no missions");
    auto started = runs_->start(run);
    if (!started) {
      return send_error(res, started.error().code == core::ErrorCode::Overflow ? 409 : 400, started.error().message);
    }
    send_json(res, {{"ok", true}}, 202);
  });

  s.Post("/api/run/stop", [this](const httplib::Request&, httplib::Response& res) {
    if (runs_) runs_->stop();
    send_json(res, {{"ok", true}});
  });
  s.Post("/api/run/abort", [this](const httplib::Request&, httplib::Response& res) {
    if (runs_) runs_->abort();
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
    // Each stream holds a worker while open: a bounded number, so that the
    // API always has workers left.
    auto slot = Slot::take(streams_, options_.max_streams);
    if (!slot) {
      return send_busy(res, 503, 5,
                       fmt::format("{} event streams are open, the most this studio serves (--max-streams): close a "
                                   "tab or try again",
                                   options_.max_streams));
    }
    auto sub = hub_.subscribe();
    const auto heartbeat = options_.heartbeat;
    const auto batch = options_.batch;
    res.set_header("Cache-Control", "no-cache");
    res.set_header("X-Accel-Buffering", "no");
    res.set_chunked_content_provider("text/event-stream",
                                     [sub, slot, heartbeat, batch](std::size_t, httplib::DataSink& sink) {
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
}

}  // namespace strata::studio
