#include "studio/model_patch.h"

#include <algorithm>
#include <optional>
#include <random>
#include <string_view>
#include <vector>

#include <fmt/format.h>

namespace strata::studio {

using nlohmann::json;

ModelCache::ModelCache() {
  std::random_device rd;
  prefix_ = fmt::format("{:08x}{:08x}-", rd(), rd());
}

std::shared_ptr<const json> ModelCache::keep(json model) {
  std::lock_guard lock(mutex_);
  std::string rev = prefix_ + std::to_string(next_++);
  model["rev"] = rev;
  auto kept = std::make_shared<const json>(std::move(model));
  entries_.emplace_back(std::move(rev), kept);
  while (entries_.size() > kEntries) entries_.pop_front();
  return kept;
}

std::shared_ptr<const json> ModelCache::find(const std::string& rev) const {
  std::lock_guard lock(mutex_);
  for (const auto& [r, m] : entries_) {
    if (r == rev) return m;
  }
  return nullptr;
}

namespace {

std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  for (;;) {
    const std::size_t nl = text.find('\n', start);
    if (nl == std::string_view::npos) {
      lines.push_back(text.substr(start));
      return lines;
    }
    lines.push_back(text.substr(start, nl - start));
    start = nl + 1;
  }
}

struct Shift {
  std::int64_t from = 0;  // lines (1-based) from here on move
  std::int64_t by = 0;
};

// Whether element `old` (a place or transition), moved by `shift`, is `now`.
bool same_element(const json& old, const json& now, const Shift* shift) {
  if (!old.is_object() || !now.is_object() || old.size() != now.size()) return old == now;
  for (auto it = now.begin(); it != now.end(); ++it) {
    auto o = old.find(it.key());
    if (o == old.end()) return false;
    if (shift && it.key() == "line" && o->is_number_integer()) {
      const std::int64_t line = o->get<std::int64_t>();
      if (!it->is_number_integer() || it->get<std::int64_t>() != (line >= shift->from ? line + shift->by : line)) {
        return false;
      }
    } else if (*o != *it) {
      return false;
    }
  }
  return true;
}

// The splice of old into now: common ends kept, the middle replaced.
std::optional<json> splice(const json& old, const json& now, const Shift* shift) {
  const std::size_t n = old.size(), m = now.size();
  std::size_t pre = 0;
  while (pre < n && pre < m && same_element(old[pre], now[pre], shift)) ++pre;
  std::size_t suf = 0;
  while (suf < n - pre && suf < m - pre && same_element(old[n - 1 - suf], now[m - 1 - suf], shift)) ++suf;
  if (pre == n && pre == m) return std::nullopt;
  json insert = json::array();
  for (std::size_t i = pre; i < m - suf; ++i) insert.push_back(now[i]);
  return json{{"at", pre}, {"remove", n - pre - suf}, {"insert", std::move(insert)}};
}

bool is_element_array(const std::string& key) { return key == "places" || key == "transitions"; }

json net_patch(const json& old, std::size_t from, const json& now, const Shift* shift) {
  json entry = {{"from", from}, {"shift", shift != nullptr}};
  json fields = json::object();
  for (auto it = now.begin(); it != now.end(); ++it) {
    if (is_element_array(it.key())) continue;
    auto o = old.find(it.key());
    if (o == old.end() || *o != *it) fields[it.key()] = *it;
  }
  if (!fields.empty()) entry["fields"] = std::move(fields);
  // Both arms lvalues: `? old[key] : json::array()` would copy the array
  // (a 5,000-transition net's, twice per edit: half of an edit's time).
  static const json empty = json::array();
  for (const char* key : {"places", "transitions"}) {
    const json& a = old.contains(key) ? old[key] : empty;
    const json& b = now.contains(key) ? now[key] : empty;
    if (auto s = splice(a, b, shift)) entry[key] = std::move(*s);
  }
  return entry;
}

}  // namespace

json model_patch(const json& before, const json& after) {
  json patch = json::object();
  // The text, by lines: the common first and last lines are kept.
  const std::string old_text = before.value("text", ""), new_text = after.value("text", "");
  const auto a = split_lines(old_text), b = split_lines(new_text);
  std::size_t pre = 0;
  while (pre < a.size() && pre < b.size() && a[pre] == b[pre]) ++pre;
  std::size_t suf = 0;
  while (suf < a.size() - pre && suf < b.size() - pre && a[a.size() - 1 - suf] == b[b.size() - 1 - suf]) ++suf;
  json insert = json::array();
  for (std::size_t i = pre; i < b.size() - suf; ++i) insert.push_back(std::string(b[i]));
  patch["text"] = {{"at", pre}, {"remove", a.size() - pre - suf}, {"insert", std::move(insert)}};
  // Lines after the changed ones moved by the difference.
  const Shift shift{static_cast<std::int64_t>(a.size() - suf) + 1,
                    static_cast<std::int64_t>(b.size()) - static_cast<std::int64_t>(a.size())};
  patch["shift"] = {{"from", shift.from}, {"by", shift.by}};

  json fields = json::object(), drop = json::array();
  for (auto it = after.begin(); it != after.end(); ++it) {
    if (it.key() == "text" || it.key() == "nets" || it.key() == "rev") continue;
    auto o = before.find(it.key());
    if (o == before.end() || *o != *it) fields[it.key()] = *it;
  }
  for (auto it = before.begin(); it != before.end(); ++it) {
    if (it.key() != "rev" && !after.contains(it.key())) drop.push_back(it.key());
  }
  patch["fields"] = std::move(fields);
  patch["drop"] = std::move(drop);

  // Nets by name. The line shift applies to the nets of the edited text
  // (editable: declared in the file itself); imports keep their lines.
  const json empty = json::array();
  const json& old_nets = before.contains("nets") ? before["nets"] : empty;
  json nets = json::array();
  for (const auto& net : after.contains("nets") ? after["nets"] : empty) {
    const std::string name = net.value("name", "");
    std::size_t from = old_nets.size();
    for (std::size_t i = 0; i < old_nets.size(); ++i) {
      if (old_nets[i].value("name", "") == name) {
        from = i;
        break;
      }
    }
    if (from == old_nets.size()) {
      nets.push_back({{"net", net}});
      continue;
    }
    const bool shifted = shift.by != 0 && net.value("editable", false) && old_nets[from].value("editable", false);
    nets.push_back(net_patch(old_nets[from], from, net, shifted ? &shift : nullptr));
  }
  patch["nets"] = std::move(nets);
  return patch;
}

}  // namespace strata::studio
