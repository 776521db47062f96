#include "studio/server.h"

// The studio's file API: the mission list, a mission's model, check, edit,
// verify, and the writes of text and layout (versioned: ETag, If-Match).

#include <filesystem>
#include <mutex>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <httplib.h>

#include "coral/verify_report.h"
#include "core/mission_language.h"
#include "run/bound_options.h"
#include "studio/file_watcher.h"
#include "studio/http_answers.h"
#include "studio/mission_model.h"
#include "studio/model_patch.h"
#include "studio/prolog_model.h"

namespace strata::studio {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

}  // namespace

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

void StudioServer::file_routes(httplib::Server& s) {
  const tactical::Catalogue& catalogue = *options_.catalogue;
  // A JSON body whose "path" names a mission inside the folder (it may not
  // exist yet), or nullopt with the error answered.
  auto mission_body = [this](const httplib::Request& req, httplib::Response& res) -> std::optional<json> {
    auto body = json_body(req, res);
    if (!body) return std::nullopt;
    auto real = sandbox_.resolve(body->value("path", ""), true);
    if (!real) {
      send_path_error(res, real.error());
      return std::nullopt;
    }
    return body;
  };

  s.Get("/api/files", [this](const httplib::Request&, httplib::Response& res) {
    json missions = json::array();
    std::size_t unnamed = 0;  // files whose names are not UTF-8: the page could not name them
    for (const auto& path : sandbox_.list({".coral", ".pl"}, &unnamed)) {
      missions.push_back({{"path", path}, {"kind", mission_kind(path)}});
    }
    json body = {{"root", sandbox_.root().string()},
                 {"files", sandbox_.list({".coral"})},
                 {"missions", missions},
                 {"logs", sandbox_.list({".jsonl"}, &unnamed)}};
    if (unnamed > 0) {
      body["unlisted"] = fmt::format("{} file{} whose name is not UTF-8 (rename to open in the studio)", unnamed,
                                     unnamed == 1 ? "" : "s");
    }
    send_json(res, body);
  });

  s.Get("/api/mission", [this, &catalogue](const httplib::Request& req, httplib::Response& res) {
    const std::string path = req.get_param_value("path");
    auto real = sandbox_.resolve(path);
    if (!real) return send_path_error(res, real.error());
    if (core::mission_language(path) == core::MissionLanguage::Prolog) {
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

  s.Post("/api/check", [this, &catalogue, mission_body](const httplib::Request& req, httplib::Response& res) {
    auto body = mission_body(req, res);
    if (!body) return;
    const std::string path = body->value("path", "");
    send_json(res, *models_.keep(compile_mission(sandbox_, path, body->value("text", ""), catalogue).model));
  });

  s.Post("/api/edit", [this, &catalogue, mission_body](const httplib::Request& req, httplib::Response& res) {
    auto body = mission_body(req, res);
    if (!body) return;
    const std::string path = body->value("path", "");
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

  s.Post("/api/verify", [this, &catalogue, mission_body](const httplib::Request& req, httplib::Response& res) {
    auto body = mission_body(req, res);
    if (!body) return;
    // Each may take its memory limit: a bounded number at once.
    auto slot = Slot::take(verifies_, options_.max_verifies);
    if (!slot) {
      return send_busy(res, 429, 2,
                       fmt::format("{} verifications are running, the most this studio runs at once "
                                   "(--max-verifies): try again when one ends",
                                   options_.max_verifies));
    }
    const std::string path = body->value("path", "");
    std::optional<std::string> text;
    if (body->contains("text") && (*body)["text"].is_string()) text = (*body)["text"].get<std::string>();
    CompiledMission m = compile_mission(sandbox_, path, text, catalogue);
    if (!m.program)
      return send_json(res, {{"error", "the mission does not compile"}, {"diagnostics", m.model["diagnostics"]}}, 422);
    coral::VerifyOptions vo;
    vo.sources = m.sources.get();
    vo.timing = run::bound_options(catalogue);  // the mission's `require`
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
    const core::MissionLanguage language = core::mission_language(path);
    if (language == core::MissionLanguage::Prolog) {
      return send_error(
          res, 403, fmt::format("'{}': PROLOG missions are read-only in the studio; edit them in a text editor", path));
    }
    if (language != core::MissionLanguage::Coral)
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
    if (core::mission_language(path) != core::MissionLanguage::Coral)
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
}

}  // namespace strata::studio
