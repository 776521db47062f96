#pragma once
// The news of a run, for every page watching: events are published from the
// run's thread and delivered to each connected Server-Sent Events stream in
// order. The hub also keeps what a page opened mid-run needs to catch up
// (the `snapshot` event of docs/studio.md): the nets, the marking of every
// instance, the actions in flight, telemetry and reports so far.
//
// Threads: publish() from any thread; each subscriber is read by its own
// HTTP worker thread. A slow reader never blocks publish(): its queue is
// bounded, and when it overflows the oldest `fired` events are dropped (the
// marking they carry is superseded by later ones) before anything else.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace strata::studio {

class EventHub {
 public:
  class Subscription;

  explicit EventHub(std::size_t max_queue = 4096) : max_queue_(max_queue) {}

  // Sends `name` with `data` to every subscriber and folds it into the
  // snapshot: run_start resets it; phase_start, fired, action_* and
  // phase_end update the instances and in-flight list; telemetry and report
  // append; run_end records the outcome.
  void publish(const std::string& name, const nlohmann::json& data);

  // A new stream: its first event is the snapshot.
  std::shared_ptr<Subscription> subscribe();
  // Wakes every subscriber so its stream can end (server stopping).
  void close();
  bool closed() const;

  nlohmann::json snapshot() const;
  std::size_t subscribers() const;

  class Subscription {
   public:
    // Waits up to `wait` for events; returns them as SSE text ("event: ...\n
    // data: ...\n\n" each), "" when none came, nullopt when the hub closed.
    std::optional<std::string> next(std::chrono::milliseconds wait);
    ~Subscription();

   private:
    friend class EventHub;
    EventHub* hub_ = nullptr;
    std::deque<std::pair<std::string, std::string>> queue_;  // name, SSE text
    std::uint64_t dropped_ = 0;
  };

 private:
  void fold(const std::string& name, const nlohmann::json& data);
  void unsubscribe(Subscription* s);

  const std::size_t max_queue_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<Subscription*> subs_;
  bool closed_ = false;
  // The snapshot.
  nlohmann::json run_ = nullptr;  // run_start's data
  std::map<std::uint64_t, nlohmann::json> instances_;
  std::map<std::uint64_t, nlohmann::json> in_flight_;
  nlohmann::json telemetry_ = nlohmann::json::array();
  nlohmann::json reports_ = nlohmann::json::array();
  nlohmann::json ended_ = nullptr;
};

// "event: NAME\ndata: JSON\n\n".
std::string sse_text(const std::string& name, const nlohmann::json& data);

}  // namespace strata::studio
