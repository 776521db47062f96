// HTTP answers of the studio's server (http_answers.h).
#include "studio/http_answers.h"

#include <cctype>
#include <cstdlib>

#include <fmt/format.h>

namespace strata::studio {

using nlohmann::json;

// The bytes as they are: a sized content provider, which the HTTP library
// sends without compressing them per request (set_content() would
// brotli-compress every JSON answer and page asset for a browser, at
// quality 11, on loopback).
void send_bytes(httplib::Response& res, std::string bytes, const char* mime) {
  auto body = std::make_shared<const std::string>(std::move(bytes));
  res.set_content_provider(body->size(), mime, [body](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
    if (offset > body->size()) return false;
    return sink.write(body->data() + offset, std::min(length, body->size() - offset));
  });
}

void send_bytes_view(httplib::Response& res, std::string_view bytes, const char* mime) {
  res.set_content_provider(bytes.size(), mime,
                           [bytes](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
                             if (offset > bytes.size()) return false;
                             return sink.write(bytes.data() + offset, std::min(length, bytes.size() - offset));
                           });
}

void send_json(httplib::Response& res, const json& body, int status) {
  res.status = status;
  send_bytes(res, body.dump(-1, ' ', false, json::error_handler_t::replace), "application/json");
}

void send_error(httplib::Response& res, int status, const std::string& message) {
  send_json(res, {{"error", message}}, status);
}

void send_busy(httplib::Response& res, int status, int retry_after_s, const std::string& message) {
  res.set_header("Retry-After", std::to_string(retry_after_s));
  send_error(res, status, message);
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

// A string field of the body, or nullopt (and a 400 sent) when it is there
// but not a string.
std::optional<std::string> string_field(const json& body, const char* key, httplib::Response& res) {
  if (!body.contains(key) || body[key].is_null()) return std::string();
  if (!body[key].is_string()) {
    send_error(res, 400, fmt::format("'{}' must be a string", key));
    return std::nullopt;
  }
  return body[key].get<std::string>();
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Whether an If-Match header names `etag` (a list, weak tags compared by
// their value, `*` for any current version).
bool if_match(const std::string& header, const std::string& etag) {
  std::size_t at = 0;
  while (at <= header.size()) {
    std::size_t comma = header.find(',', at);
    if (comma == std::string::npos) comma = header.size();
    std::string tag = header.substr(at, comma - at);
    const auto first = tag.find_first_not_of(" \t"), last = tag.find_last_not_of(" \t");
    tag = first == std::string::npos ? "" : tag.substr(first, last - first + 1);
    if (tag.starts_with("W/")) tag = tag.substr(2);
    if (tag == "*" || tag == etag) return true;
    at = comma + 1;
  }
  return false;
}

// Whether an Accept-Encoding header accepts `coding` (a q of 0 refuses it).
bool accepts(const std::string& header, std::string_view coding) {
  std::size_t at = 0;
  while (at < header.size()) {
    std::size_t comma = header.find(',', at);
    if (comma == std::string::npos) comma = header.size();
    std::string item = header.substr(at, comma - at);
    at = comma + 1;
    const auto semi = item.find(';');
    std::string name = lower(item.substr(0, semi));
    name.erase(0, name.find_first_not_of(" \t"));
    name.erase(name.find_last_not_of(" \t") + 1);
    if (name != coding && name != "*") continue;
    if (semi != std::string::npos) {
      const auto q = item.find("q=", semi);
      if (q != std::string::npos && std::strtod(item.c_str() + q + 2, nullptr) <= 0.0) return false;
    }
    return true;
  }
  return false;
}

}  // namespace strata::studio
