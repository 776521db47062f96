#pragma once
// How the studio's server answers over HTTP: bodies sent as they are (never
// compressed per request), JSON and `{"error": ...}` with the right status,
// a request's JSON body and fields, and the headers it reads (If-Match,
// Accept-Encoding). docs/studio.md, "JSON API".
#include <optional>
#include <string>
#include <string_view>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/result.h"

namespace strata::studio {

void send_bytes(httplib::Response& res, std::string bytes, const char* mime);
// `bytes` must outlive the answer (an embedded asset).
void send_bytes_view(httplib::Response& res, std::string_view bytes, const char* mime);
void send_json(httplib::Response& res, const nlohmann::json& body, int status = 200);
void send_error(httplib::Response& res, int status, const std::string& message);
// An error that says when to come back (Retry-After, seconds): 429, 503.
void send_busy(httplib::Response& res, int status, int retry_after_s, const std::string& message);
// A refused or missing path: its status (status_of) and message.
void send_path_error(httplib::Response& res, const core::Error& e);
int status_of(const core::Error& e);
const char* mime_of(const std::string& path);

// The request's JSON object, or nullopt with a 400 already sent.
std::optional<nlohmann::json> json_body(const httplib::Request& req, httplib::Response& res);
// body[key] as a string, or nullopt with a 400 already sent.
std::optional<std::string> string_field(const nlohmann::json& body, const char* key, httplib::Response& res);

std::string lower(std::string s);
// Whether an If-Match header names `etag` (a list, weak tags compared by
// their value, `*` for any current version).
bool if_match(const std::string& header, const std::string& etag);
// Whether an Accept-Encoding header accepts `coding` (a q of 0 refuses it).
bool accepts(const std::string& header, std::string_view coding);

}  // namespace strata::studio
