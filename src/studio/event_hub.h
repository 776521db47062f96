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
#include <functional>
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
  // phase_end update the instances and in-flight list (phase_end takes out
  // the PHASE action that started the instance, data "action", and every
  // action of the instance, and keeps the instance's last marking as the
  // final one of its net); telemetry and report append; run_end records the
  // outcome and empties the in-flight list.
  void publish(const std::string& name, nlohmann::json data);

  // The same with the data built only when a reader or the snapshot first
  // needs it (once, on that thread): the publishing thread pays for a
  // closure, not for JSON. `instance` and `id` are the data's keys of the
  // same names, which the snapshot needs without building it.
  // For phase_end, `id` is the PHASE action that started the instance (0
  // for the mission) and `net` the net's name.
  struct Keys {
    std::uint64_t instance = 0;
    std::uint64_t id = 0;
    std::string net = {};
  };
  void publish_lazy(const std::string& name, const Keys& keys, std::function<nlohmann::json()> make);

  // A new stream: its first event is the snapshot.
  std::shared_ptr<Subscription> subscribe();
  // Wakes every subscriber so its stream can end (server stopping).
  void close();
  bool closed() const;

  nlohmann::json snapshot() const;
  std::size_t subscribers() const;
  // Events kept for readers: those some subscriber has not taken yet, and
  // those the publisher let go of that no reader has freed yet.
  std::size_t kept() const;

  class Subscription {
   public:
    // Waits up to `wait` for events; returns them as SSE text ("event: ...\n
    // data: ...\n\n" each), "" when none came, nullopt when the hub closed.
    // With `settle`, it looks every `settle` instead of being woken by
    // publish(), and once there is news it waits for a look with nothing
    // new (or 5 looks at most): a burst (a lockstep run publishes hundreds
    // of events in a few ms) costs the run no wake-ups and is read in one
    // go, after it.
    std::optional<std::string> next(std::chrono::milliseconds wait,
                                    std::chrono::milliseconds settle = std::chrono::milliseconds(0));
    // Events published and not yet taken by next().
    std::uint64_t behind() const;
    ~Subscription();

   private:
    friend class EventHub;
    EventHub* hub_ = nullptr;
    std::uint64_t next_seq_ = 0;  // the next event of the log to take
    std::string pending_;         // the snapshot, before anything else
  };

 private:
  struct Event;
  using EventPtr = std::shared_ptr<Event>;
  struct Instance {
    EventPtr start;   // phase_start: net, parent
    EventPtr latest;  // the last event with this instance's marking
    EventPtr fired;   // the last firing: the enabled transitions
  };
  nlohmann::json snapshot_locked() const;
  void add(EventPtr event, const Keys& keys);
  void fold(const EventPtr& event, const Keys& keys);
  void unsubscribe(Subscription* s);

  const std::size_t max_log_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<Subscription*> subs_;
  std::size_t waiting_ = 0;  // readers blocked in next() waiting for a first event
  bool closed_ = false;
  std::deque<std::shared_ptr<Event>> log_;  // only while someone subscribes
  std::uint64_t first_seq_ = 0;             // the sequence number of log_.front()
  // Events the publisher let go of while someone subscribes: readers free
  // them (with the JSON and text they built), so the publishing thread
  // does not. Bounded by max_log_; past that the publisher frees them.
  std::vector<EventPtr> unused_;
  void let_go(EventPtr e);
  // The snapshot, as the events it is made of.
  EventPtr run_;
  std::map<std::uint64_t, Instance> instances_;
  struct Flight {
    EventPtr start;  // action_start
    std::uint64_t instance = 0;
  };
  std::map<std::uint64_t, Flight> in_flight_;
  // The last instance of each net that ended: its start, last marking and
  // end. Bounded by the number of nets; kept after the run (a page loaded
  // after the end shows the final markings).
  struct Final {
    EventPtr start, latest, end;
  };
  std::map<std::string, Final> final_;
  std::vector<EventPtr> telemetry_;
  std::vector<EventPtr> reports_;
  EventPtr ended_;
};

// "event: NAME\ndata: JSON\n\n".
std::string sse_text(const std::string& name, const nlohmann::json& data);

}  // namespace strata::studio
