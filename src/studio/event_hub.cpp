#include "studio/event_hub.h"

#include <algorithm>

namespace strata::studio {

std::string sse_text(const std::string& name, const nlohmann::json& data) {
  return "event: " + name + "\ndata: " + data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n\n";
}

void EventHub::publish(const std::string& name, const nlohmann::json& data) {
  std::string text = sse_text(name, data);
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    fold(name, data);
    for (Subscription* s : subs_) {
      if (s->queue_.size() >= max_queue_) {
        // Drop the oldest firing: a later one carries a newer marking.
        auto it = std::find_if(s->queue_.begin(), s->queue_.end(), [](const auto& e) { return e.first == "fired"; });
        if (it == s->queue_.end()) it = s->queue_.begin();
        s->queue_.erase(it);
        ++s->dropped_;
      }
      s->queue_.emplace_back(name, text);
    }
  }
  wake_.notify_all();
}

void EventHub::fold(const std::string& name, const nlohmann::json& d) {
  auto id = [&](const char* key) { return d.value(key, std::uint64_t{0}); };
  if (name == "run_start") {
    run_ = d;
    instances_.clear();
    in_flight_.clear();
    telemetry_ = nlohmann::json::array();
    reports_ = nlohmann::json::array();
    ended_ = nullptr;
  } else if (name == "phase_start") {
    instances_[id("instance")] = {{"instance", d.value("instance", 0)}, {"net", d.value("net", "")},
                                  {"parent", d.value("parent", 0)}, {"marking", d.value("marking", nlohmann::json::object())}};
  } else if (name == "fired" || name == "action_finish") {
    auto it = instances_.find(id("instance"));
    if (it != instances_.end() && d.contains("marking")) it->second["marking"] = d["marking"];
    if (name == "fired" && it != instances_.end()) it->second["enabled"] = d.value("enabled", nlohmann::json::array());
    if (name == "action_finish") in_flight_.erase(id("id"));
  } else if (name == "action_start") {
    in_flight_[id("id")] = d;
  } else if (name == "phase_end") {
    instances_.erase(id("instance"));
  } else if (name == "telemetry") {
    telemetry_.push_back({d.value("t", 0.0), d.value("depth", 0.0), d.contains("setpoint") ? d["setpoint"] : nlohmann::json(nullptr)});
  } else if (name == "report") {
    reports_.push_back(d);
  } else if (name == "run_end") {
    ended_ = d;
    in_flight_.clear();
  }
}

nlohmann::json EventHub::snapshot() const {
  std::lock_guard lock(mutex_);
  nlohmann::json instances = nlohmann::json::array(), flights = nlohmann::json::array();
  for (const auto& [k, v] : instances_) instances.push_back(v);
  for (const auto& [k, v] : in_flight_) flights.push_back(v);
  auto field = [&](const char* key, nlohmann::json otherwise) {
    return run_.is_object() && run_.contains(key) ? run_[key] : otherwise;
  };
  nlohmann::json s = {{"run", field("run", nullptr)},
                      {"mission", field("mission", nullptr)},
                      {"nets", field("nets", nlohmann::json::array())},
                      {"instances", instances},
                      {"in_flight", flights},
                      {"telemetry", telemetry_},
                      {"reports", reports_},
                      {"ended", ended_}};
  return s;
}

std::shared_ptr<EventHub::Subscription> EventHub::subscribe() {
  auto s = std::make_shared<Subscription>();
  s->hub_ = this;
  nlohmann::json snap = snapshot();
  std::lock_guard lock(mutex_);
  s->queue_.emplace_back("snapshot", sse_text("snapshot", snap));
  subs_.push_back(s.get());
  return s;
}

void EventHub::unsubscribe(Subscription* s) {
  std::lock_guard lock(mutex_);
  std::erase(subs_, s);
}

void EventHub::close() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  wake_.notify_all();
}

bool EventHub::closed() const {
  std::lock_guard lock(mutex_);
  return closed_;
}

std::size_t EventHub::subscribers() const {
  std::lock_guard lock(mutex_);
  return subs_.size();
}

std::optional<std::string> EventHub::Subscription::next(std::chrono::milliseconds wait) {
  std::unique_lock lock(hub_->mutex_);
  hub_->wake_.wait_for(lock, wait, [&] { return !queue_.empty() || hub_->closed_; });
  if (queue_.empty() && hub_->closed_) return std::nullopt;
  std::string out;
  for (auto& [name, text] : queue_) out += text;
  queue_.clear();
  return out;
}

EventHub::Subscription::~Subscription() {
  if (hub_) hub_->unsubscribe(this);
}

}  // namespace strata::studio
