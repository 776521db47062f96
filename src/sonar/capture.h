#pragma once
// Capture: the Sonar Manager's reading thread (docs/sonar.md, "Capture").
// It connects to the vehicle's sonar socket, reads with a large buffer,
// decodes frames (protocol/sonar_frame.h) and hands them to processing
// through a FrameQueue. It never waits for processing: when the queue holds
// its cap of pings, further pings are dropped (counted) until it drains, so
// the socket is always drained and the vehicle never has to drop for us.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <variant>

#include "protocol/sonar_frame.h"

namespace strata::sonar {

// Capture is connected (the first item of a stream that connected).
struct StreamConnected {};

// The last item of a stream that ended without a SonarEnd.
struct StreamClosed {
  bool connected = false;  // false: it never connected (refused until the timeout)
  bool stopped = false;    // true: Capture::stop() was called
  std::string why;         // for people: "connection refused", "the vehicle closed the connection", ...
};

struct CaptureItem {
  std::variant<StreamConnected, protocol::SonarPing, protocol::SonarStatus, protocol::SonarEnd, StreamClosed> what;
  // The stream's seq gaps and the pings they lost, when this item was read.
  std::uint64_t seq_gaps = 0;
  std::uint64_t lost_pings = 0;
};

// Capture to processing: many items, two threads. push() never blocks.
class FrameQueue {
 public:
  explicit FrameQueue(std::size_t ping_capacity) : capacity_(ping_capacity) {}
  // Takes the item, unless it is a ping and `ping_capacity` pings are already
  // waiting: then it is dropped and counted, and push() returns false.
  // Other items are always taken (there are few, and they end the stream).
  bool push(CaptureItem item);
  // The oldest item, or nullopt after `wait`.
  std::optional<CaptureItem> pop(std::chrono::milliseconds wait);

  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }
  std::size_t peak() const { return peak_.load(std::memory_order_relaxed); }
  std::size_t capacity() const { return capacity_; }

 private:
  const std::size_t capacity_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<CaptureItem> items_;
  std::size_t pings_ = 0;
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::size_t> peak_{0};
};

struct CaptureOptions {
  std::string host = "127.0.0.1";  // IPv4 address ("localhost" too)
  std::uint16_t port = 0;
  double connect_timeout_s = 10.0;  // keep retrying a refused connection this long
  std::size_t read_buffer_bytes = 1 << 20;
  int socket_buffer_bytes = 4 << 20;  // SO_RCVBUF asked for (the kernel may cap it)
};

// What capture has seen so far. Counts only grow.
struct CaptureCounts {
  std::uint64_t bytes = 0;
  std::uint64_t pings = 0;          // decoded, whether processed or dropped from the queue
  std::uint64_t seq_gaps = 0;       // places where seq jumped ahead
  std::uint64_t lost_pings = 0;     // the seqs those jumps skipped: pings we never got
  std::uint64_t garbage_bytes = 0;  // skipped while looking for a frame's sync
  std::uint64_t bad_frames = 0;     // a header or CRC was wrong
  std::uint64_t queue_drops = 0;    // pings not processed: the queue was full
  std::size_t queue_peak = 0;       // most items waiting at once
};

class Capture {
 public:
  Capture(CaptureOptions options, FrameQueue& queue) : options_(std::move(options)), queue_(queue) {}
  ~Capture();
  Capture(const Capture&) = delete;
  Capture& operator=(const Capture&) = delete;

  // Starts the reading thread. Its items: StreamConnected, then frames,
  // then either a SonarEnd (it stops reading there) or a StreamClosed.
  void start();
  // Asks the thread to stop (within ~100 ms): it pushes StreamClosed with
  // stopped set, unless the stream had already ended. Any thread.
  void stop() { stop_.store(true); }
  void join();

  CaptureCounts counts() const;  // any thread

 private:
  void run();
  void read_stream(int fd);
  void take(protocol::SonarFrame frame, bool& ended);

  CaptureOptions options_;
  FrameQueue& queue_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> bytes_{0}, pings_{0}, seq_gaps_{0}, lost_pings_{0}, garbage_{0}, bad_frames_{0};
  std::optional<std::uint32_t> last_seq_;  // the reading thread's own
};

}  // namespace strata::sonar
