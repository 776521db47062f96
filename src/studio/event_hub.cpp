#include "studio/event_hub.h"

#include <algorithm>
#include <thread>
#include <utility>

namespace strata::studio {

std::string sse_text(const std::string& name, const nlohmann::json& data) {
  return "event: " + name + "\ndata: " + data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n\n";
}

struct EventHub::Event {
  std::string name;
  std::function<nlohmann::json()> make;  // unset when data was given
  std::once_flag built, serialised;
  nlohmann::json data;
  std::string text;

  const nlohmann::json& json() {
    std::call_once(built, [this] {
      if (make) data = make();
      make = nullptr;
    });
    return data;
  }
  const std::string& sse() {
    std::call_once(serialised, [this] { text = sse_text(name, json()); });
    return text;
  }
};

void EventHub::publish(const std::string& name, nlohmann::json data) {
  Keys keys{data.value("instance", std::uint64_t{0}),
            data.value(name == "phase_end" ? "action" : "id", std::uint64_t{0}), data.value("net", std::string())};
  auto event = std::make_shared<Event>();
  event->name = name;
  event->data = std::move(data);
  add(std::move(event), keys);
}

void EventHub::publish_lazy(const std::string& name, const Keys& keys, std::function<nlohmann::json()> make) {
  auto event = std::make_shared<Event>();
  event->name = name;
  event->make = std::move(make);
  add(std::move(event), keys);
}

void EventHub::add(EventPtr event, const Keys& keys) {
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    fold(event, keys);
    if (subs_.empty()) return;  // nobody to tell: the snapshot is enough
    log_.push_back(std::move(event));
    if (log_.size() > max_log_) {
      let_go(std::move(log_.front()));
      log_.pop_front();
      ++first_seq_;
    }
    if (waiting_ == 0) return;  // every reader is busy or settling: it will look
  }
  wake_.notify_all();
}

void EventHub::let_go(EventPtr e) {
  if (subs_.empty() || !e) return;  // nothing was built for a reader: free it here
  if (unused_.size() >= max_log_) unused_.clear();
  unused_.push_back(std::move(e));
}

void EventHub::fold(const EventPtr& e, const Keys& keys) {
  const std::string& name = e->name;
  if (name == "run_start") {
    let_go(std::exchange(run_, e));
    for (auto& [id, inst] : instances_) {
      let_go(std::move(inst.start));
      let_go(std::move(inst.latest));
      let_go(std::move(inst.fired));
    }
    instances_.clear();
    for (auto& [id, f] : in_flight_) let_go(std::move(f.start));
    in_flight_.clear();
    for (auto& [net, f] : final_) {
      let_go(std::move(f.start));
      let_go(std::move(f.latest));
      let_go(std::move(f.end));
    }
    final_.clear();
    for (auto& t : telemetry_) let_go(std::move(t));
    telemetry_.clear();
    for (auto& r : reports_) let_go(std::move(r));
    reports_.clear();
    let_go(std::exchange(ended_, nullptr));
  } else if (name == "phase_start") {
    Instance& inst = instances_[keys.instance];
    let_go(std::exchange(inst.start, e));
    let_go(std::exchange(inst.latest, e));
    let_go(std::exchange(inst.fired, nullptr));
  } else if (name == "fired" || name == "action_finish") {
    auto it = instances_.find(keys.instance);
    if (it != instances_.end()) {
      let_go(std::exchange(it->second.latest, e));
      if (name == "fired") let_go(std::exchange(it->second.fired, e));
    }
    if (name == "action_finish") {
      if (auto f = in_flight_.find(keys.id); f != in_flight_.end()) {
        let_go(std::move(f->second.start));
        in_flight_.erase(f);
      }
    }
  } else if (name == "action_start") {
    Flight& f = in_flight_[keys.id];
    let_go(std::exchange(f.start, e));
    f.instance = keys.instance;
  } else if (name == "phase_end") {
    // The phase is over: the PHASE action that ran it, and whatever its net
    // still had in flight, are no longer in flight (the engine dropped them).
    for (auto f = in_flight_.begin(); f != in_flight_.end();) {
      if ((keys.id != 0 && f->first == keys.id) || f->second.instance == keys.instance) {
        let_go(std::move(f->second.start));
        f = in_flight_.erase(f);
      } else {
        ++f;
      }
    }
    if (auto it = instances_.find(keys.instance); it != instances_.end()) {
      Final& last = final_[keys.net];
      let_go(std::exchange(last.start, std::move(it->second.start)));
      let_go(std::exchange(last.latest, std::move(it->second.latest)));
      let_go(std::exchange(last.end, e));
      let_go(std::move(it->second.fired));
      instances_.erase(it);
    }
  } else if (name == "telemetry") {
    telemetry_.push_back(e);
  } else if (name == "report") {
    reports_.push_back(e);
  } else if (name == "run_end") {
    let_go(std::exchange(ended_, e));
    for (auto& [id, f] : in_flight_) let_go(std::move(f.start));
    in_flight_.clear();
  }
}

nlohmann::json EventHub::snapshot() const {
  std::lock_guard lock(mutex_);
  return snapshot_locked();
}

nlohmann::json EventHub::snapshot_locked() const {
  const nlohmann::json none = nullptr;
  auto field = [&](const EventPtr& e, const char* key, const nlohmann::json& otherwise) -> nlohmann::json {
    if (!e) return otherwise;
    const nlohmann::json& d = e->json();
    return d.is_object() && d.contains(key) ? d[key] : otherwise;
  };
  nlohmann::json instances = nlohmann::json::array(), flights = nlohmann::json::array();
  for (const auto& [id, inst] : instances_) {
    instances.push_back({{"instance", id},
                         {"net", field(inst.start, "net", "")},
                         {"parent", field(inst.start, "parent", 0)},
                         {"marking", field(inst.latest, "marking", nlohmann::json::object())},
                         {"enabled", field(inst.fired, "enabled", nlohmann::json::array())}});
  }
  for (const auto& [id, f] : in_flight_) flights.push_back(f.start->json());
  nlohmann::json finals = nlohmann::json::array();
  for (const auto& [net, f] : final_) {
    finals.push_back({{"instance", field(f.start, "instance", 0)},
                      {"net", field(f.start, "net", net)},
                      {"parent", field(f.start, "parent", 0)},
                      {"marking", field(f.latest, "marking", nlohmann::json::object())},
                      {"exit", field(f.end, "exit", "")},
                      {"cancelled", field(f.end, "cancelled", false)}});
  }
  nlohmann::json telemetry = nlohmann::json::array(), reports = nlohmann::json::array();
  for (const auto& e : telemetry_) {
    nlohmann::json row = {field(e, "t", 0.0), field(e, "depth", 0.0), field(e, "setpoint", none)};
    // [t, depth, setpoint, x, y] where the sample has a position (open water).
    const nlohmann::json x = field(e, "x", none), y = field(e, "y", none);
    if (x.is_number() && y.is_number()) {
      row.push_back(x);
      row.push_back(y);
    }
    telemetry.push_back(std::move(row));
  }
  for (const auto& e : reports_) reports.push_back(e->json());
  return {{"run", field(run_, "run", none)},
          {"mission", field(run_, "mission", none)},
          {"nets", field(run_, "nets", nlohmann::json::array())},
          {"instances", instances},
          {"in_flight", flights},
          {"final", finals},
          {"telemetry", telemetry},
          {"reports", reports},
          {"ended", ended_ ? ended_->json() : none}};
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
    unused_.clear();
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

std::size_t EventHub::kept() const {
  std::lock_guard lock(mutex_);
  return log_.size() + unused_.size();
}

std::optional<std::string> EventHub::Subscription::next(std::chrono::milliseconds wait,
                                                        std::chrono::milliseconds settle) {
  std::vector<std::shared_ptr<Event>> events, done;
  std::string out;
  {
    std::unique_lock lock(hub_->mutex_);
    auto end = [&] { return hub_->first_seq_ + hub_->log_.size(); };
    auto news = [&] { return !pending_.empty() || next_seq_ < end() || hub_->closed_; };
    if (settle.count() == 0) {
      ++hub_->waiting_;
      hub_->wake_.wait_for(lock, wait, news);
      --hub_->waiting_;
    } else {
      // Polling, every `settle`: publish() never wakes this reader, so a
      // burst of events costs the publishing thread no context switches,
      // and arrives here whole.
      // Once news is there it waits for a quiet look (nothing new since the
      // last one), or at most 5 looks: a lockstep run is read after it ends,
      // a run on the wall clock at least 5 times a second.
      const auto start = std::chrono::steady_clock::now();
      std::optional<std::chrono::steady_clock::time_point> first_news;
      std::uint64_t seen_end = end();
      while (!hub_->closed_ && pending_.empty()) {
        const auto now = std::chrono::steady_clock::now();
        if (next_seq_ < end()) {
          if (!first_news) {
            first_news = now;
          } else if (end() == seen_end || now - *first_news >= 5 * settle) {
            break;
          }
        } else if (now - start >= wait) {
          break;
        }
        seen_end = end();
        lock.unlock();
        std::this_thread::sleep_for(settle);
        lock.lock();
      }
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
    // What every reader has taken leaves the log here, and is freed on this
    // thread with what the publisher let go of, outside the lock.
    std::uint64_t taken = end();
    for (const Subscription* s : hub_->subs_) taken = std::min(taken, s->next_seq_);
    for (; hub_->first_seq_ < taken; ++hub_->first_seq_) {
      done.push_back(std::move(hub_->log_.front()));
      hub_->log_.pop_front();
    }
    done.insert(done.end(), std::make_move_iterator(hub_->unused_.begin()),
                std::make_move_iterator(hub_->unused_.end()));
    hub_->unused_.clear();
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
