#include "studio/event_hub.h"

#include <algorithm>
#include <thread>

namespace strata::studio {

std::string sse_text(const std::string& name, const nlohmann::json& data) {
  return "event: " + name + "\ndata: " + data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n\n";
}

struct EventHub::Event {
  std::string name;
  nlohmann::json data;
  std::once_flag once;
  std::string text;
  const std::string& sse() {
    std::call_once(once, [this] { text = sse_text(name, data); });
    return text;
  }
};

void EventHub::publish(const std::string& name, nlohmann::json data) {
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    fold(name, data);
    if (subs_.empty()) return;  // nobody to tell: the snapshot is enough
    auto event = std::make_shared<Event>();
    event->name = name;
    event->data = std::move(data);
    log_.push_back(std::move(event));
    if (log_.size() > max_log_) {
      log_.pop_front();
      ++first_seq_;
    }
    if (waiting_ == 0) return;  // every reader is busy or settling: it will look
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
  return snapshot_locked();
}

nlohmann::json EventHub::snapshot_locked() const {
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
  std::lock_guard lock(mutex_);
  s->pending_ = sse_text("snapshot", snapshot_locked());
  s->next_seq_ = first_seq_ + log_.size();
  subs_.push_back(s.get());
  return s;
}

void EventHub::unsubscribe(Subscription* s) {
  std::lock_guard lock(mutex_);
  std::erase(subs_, s);
  if (subs_.empty()) {
    first_seq_ += log_.size();
    log_.clear();
  }
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

std::optional<std::string> EventHub::Subscription::next(std::chrono::milliseconds wait,
                                                       std::chrono::milliseconds settle) {
  std::vector<std::shared_ptr<Event>> events;
  std::string out;
  {
    std::unique_lock lock(hub_->mutex_);
    auto end = [&] { return hub_->first_seq_ + hub_->log_.size(); };
    ++hub_->waiting_;
    const bool news =
        hub_->wake_.wait_for(lock, wait, [&] { return !pending_.empty() || next_seq_ < end() || hub_->closed_; });
    --hub_->waiting_;
    if (news && settle.count() > 0 && pending_.empty() && !hub_->closed_) {
      // Let the burst finish, asleep: publish() wakes only the readers
      // waiting for a first event, so a burst costs each reader one wake-up.
      lock.unlock();
      std::this_thread::sleep_for(settle);
      lock.lock();
    }
    if (pending_.empty() && next_seq_ >= end() && hub_->closed_) return std::nullopt;
    out = std::move(pending_);
    pending_.clear();
    if (next_seq_ < hub_->first_seq_) {
      // Fell behind what the log keeps: start again from a snapshot.
      out += sse_text("snapshot", hub_->snapshot_locked());
      next_seq_ = end();
    }
    for (; next_seq_ < end(); ++next_seq_) events.push_back(hub_->log_[next_seq_ - hub_->first_seq_]);
  }
  // Serialised here, on the reader's thread, once per event for all readers.
  for (const auto& e : events) out += e->sse();
  return out;
}

std::uint64_t EventHub::Subscription::behind() const {
  std::lock_guard lock(hub_->mutex_);
  return hub_->first_seq_ + hub_->log_.size() - next_seq_ + (pending_.empty() ? 0 : 1);
}

EventHub::Subscription::~Subscription() {
  if (hub_) hub_->unsubscribe(this);
}

}  // namespace strata::studio
