#pragma once
// The news of a run, for every page watching: events are published from the
// run's thread and delivered to each connected Server-Sent Events stream in
// order. The hub also keeps what a page opened mid-run needs to catch up
// (the `snapshot` event of docs/studio.md): the nets, the marking of every
// instance, the actions in flight, telemetry and reports so far.
//
// Cost to the run: publish() folds the event into the snapshot and appends
// one shared pointer to a log; nothing is copied per subscriber and nothing
// is serialised on the publishing thread. Each stream's reader turns the
// events it takes into SSE text (once per event, shared by every reader).
//
// Threads: publish() from any thread; each subscription is read by its own
// HTTP worker thread. A slow reader never blocks publish(): the log keeps
// the last `max_log` events, and a reader that falls further behind gets a
// fresh snapshot instead of what it missed.
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

  explicit EventHub(std::size_t max_log = 8192) : max_log_(max_log) {}

  // Sends `name` with `data` to every subscriber and folds it into the
  // snapshot: run_start resets it; phase_start, fired, action_* and
  // phase_end update the instances and in-flight list; telemetry and report
  // append; run_end records the outcome.
  void publish(const std::string& name, nlohmann::json data);

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
    // With `settle`, once the first event is there it waits that much more
    // before taking what has come: a burst (a lockstep run publishes
    // hundreds of events in a few ms) is then read in one go, after it.
    std::optional<std::string> next(std::chrono::milliseconds wait,
                                    std::chrono::milliseconds settle = std::chrono::milliseconds(0));
    // Events published and not yet taken by next().
    std::uint64_t behind() const;
    ~Subscription();

   private:
    friend class EventHub;
    EventHub* hub_ = nullptr;
    std::uint64_t next_seq_ = 0;   // the next event of the log to take
    std::string pending_;          // the snapshot, before anything else
  };

 private:
  struct Event;
  nlohmann::json snapshot_locked() const;
  void fold(const std::string& name, const nlohmann::json& data);
  void unsubscribe(Subscription* s);

  const std::size_t max_log_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<Subscription*> subs_;
  std::size_t waiting_ = 0;  // readers blocked in next() waiting for a first event
  bool closed_ = false;
  std::deque<std::shared_ptr<Event>> log_;  // only while someone subscribes
  std::uint64_t first_seq_ = 0;             // the sequence number of log_.front()
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
