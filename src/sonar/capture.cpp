#include "sonar/capture.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <vector>

#include <fmt/format.h>

#include "core/result.h"

namespace strata::sonar {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kPollMs = 100;  // how soon stop() is noticed

// Nobody listening yet (the vehicle is starting): try again. A reset while
// connecting is not retried: the vehicle answered and dropped us (its data
// may be lost with the reset), and another attempt could land in a listen
// queue that nobody reads.
bool worth_retrying(int error) {
  return error == ECONNREFUSED || error == ETIMEDOUT || error == ENETUNREACH || error == EHOSTUNREACH ||
         error == EAGAIN;
}

// One non-blocking connection attempt of at most `bound_ms`: 0 or an errno.
int try_connect(int fd, const sockaddr_in& address, int bound_ms) {
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0) return 0;
  if (errno != EINPROGRESS) return errno;
  pollfd p{fd, POLLOUT, 0};
  const int ready = ::poll(&p, 1, bound_ms);
  if (ready < 0) return errno;
  if (ready == 0) return ETIMEDOUT;
  int error = 0;
  socklen_t length = sizeof error;
  if (::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length) != 0) return errno;
  return error;
}

// A connected non-blocking socket, retrying while refused until the timeout.
core::Result<int> connect_with_retry(const CaptureOptions& o, const std::atomic<bool>& stop) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(o.port);
  const std::string host = o.host == "localhost" ? "127.0.0.1" : o.host;
  if (::inet_pton(AF_INET, host.c_str(), &address.sin_addr) != 1) {
    return core::make_error(core::ErrorCode::InvalidInput, fmt::format("'{}' is not an IPv4 address", o.host));
  }
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(std::max(o.connect_timeout_s, 0.0)));
  for (;;) {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) return core::make_error(core::ErrorCode::Io, fmt::format("socket: {}", std::strerror(errno)));
    const auto left_ms = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    const int error = try_connect(fd, address, static_cast<int>(std::clamp<long long>(left_ms, 1, 1000)));
    if (error == 0) return fd;
    ::close(fd);
    if (error == ECONNRESET || error == ECONNABORTED) {
      return core::make_error(core::ErrorCode::Io, "the vehicle reset the connection as it was made");
    }
    std::string why = error == ETIMEDOUT ? "no answer" : std::strerror(error);
    if (!why.empty()) why[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(why[0])));
    if (!worth_retrying(error) || Clock::now() >= deadline) {
      return core::make_error(core::ErrorCode::Timeout, fmt::format("could not connect to {}:{} within {:g} s ({})",
                                                                    o.host, o.port, o.connect_timeout_s, why));
    }
    for (int i = 0; i < 10 && !stop.load() && Clock::now() < deadline; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (stop.load()) return core::make_error(core::ErrorCode::Closed, "stopped before connecting");
  }
}

}  // namespace

bool FrameQueue::push(CaptureItem item) {
  const bool ping = std::holds_alternative<protocol::SonarPing>(item.what);
  {
    std::lock_guard lock(mutex_);
    if (ping && pings_ >= capacity_) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    pings_ += ping ? 1 : 0;
    items_.push_back(std::move(item));
    if (items_.size() > peak_.load(std::memory_order_relaxed)) peak_.store(items_.size(), std::memory_order_relaxed);
  }
  ready_.notify_one();
  return true;
}

std::optional<CaptureItem> FrameQueue::pop(std::chrono::milliseconds wait) {
  std::unique_lock lock(mutex_);
  if (!ready_.wait_for(lock, wait, [&] { return !items_.empty(); })) return std::nullopt;
  CaptureItem item = std::move(items_.front());
  items_.pop_front();
  if (std::holds_alternative<protocol::SonarPing>(item.what)) --pings_;
  return item;
}

Capture::~Capture() {
  stop();
  join();
}

void Capture::start() {
  thread_ = std::thread([this] { run(); });
}

void Capture::join() {
  if (thread_.joinable()) thread_.join();
}

CaptureCounts Capture::counts() const {
  CaptureCounts c;
  c.bytes = bytes_.load(std::memory_order_relaxed);
  c.pings = pings_.load(std::memory_order_relaxed);
  c.seq_gaps = seq_gaps_.load(std::memory_order_relaxed);
  c.lost_pings = lost_pings_.load(std::memory_order_relaxed);
  c.garbage_bytes = garbage_.load(std::memory_order_relaxed);
  c.bad_frames = bad_frames_.load(std::memory_order_relaxed);
  c.queue_drops = queue_.dropped();
  c.queue_peak = queue_.peak();
  return c;
}

void Capture::run() {
  auto fd = connect_with_retry(options_, stop_);
  if (!fd) {
    const bool stopped = fd.error().code == core::ErrorCode::Closed;
    // Reset as it was made: the vehicle was there and went away.
    const bool reached = fd.error().code == core::ErrorCode::Io;
    queue_.push({StreamClosed{reached, stopped, fd.error().message}});
    return;
  }
  // A large receive buffer absorbs bursts while this thread is descheduled.
  ::setsockopt(fd.value(), SOL_SOCKET, SO_RCVBUF, &options_.socket_buffer_bytes, sizeof options_.socket_buffer_bytes);
  queue_.push({StreamConnected{}});
  read_stream(fd.value());
  ::close(fd.value());
}

void Capture::read_stream(int fd) {
  protocol::SonarDecoder decoder;
  std::vector<char> buffer(std::max<std::size_t>(options_.read_buffer_bytes, 4096));
  auto closed = [&](bool stopped, std::string why) {
    if (decoder.buffered() > 0) why += fmt::format("; {} bytes of a cut frame left", decoder.buffered());
    queue_.push({StreamClosed{true, stopped, std::move(why)}, seq_gaps_.load(), lost_pings_.load()});
  };
  bool ended = false;
  // The vehicle sends a status frame as soon as a reader connects; a peer
  // that says nothing for the connect timeout is not a sonar stream, and
  // waiting on it would never end.
  const auto quiet_limit = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                              std::chrono::duration<double>(std::max(options_.connect_timeout_s, 1.0)));
  while (!ended) {
    if (stop_.load()) return closed(true, "stopped");
    if (decoder.frames() == 0 && Clock::now() >= quiet_limit) {
      return closed(false,
                    fmt::format("connected, but nothing came from the vehicle within {:g} s (not a sonar socket?)",
                                std::max(options_.connect_timeout_s, 1.0)));
    }
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, kPollMs);
    if (ready < 0 && errno != EINTR) return closed(false, fmt::format("poll: {}", std::strerror(errno)));
    if (ready <= 0) continue;
    const ssize_t n = ::recv(fd, buffer.data(), buffer.size(), 0);
    if (n == 0) return closed(false, "the vehicle closed the connection");
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK) continue;
      return closed(false, errno == ECONNRESET ? "the vehicle reset the connection" : std::strerror(errno));
    }
    bytes_.fetch_add(static_cast<std::uint64_t>(n), std::memory_order_relaxed);
    decoder.feed(std::string_view(buffer.data(), static_cast<std::size_t>(n)));
    while (!ended) {
      auto frame = decoder.next();
      if (!frame) break;
      take(std::move(*frame), ended);
    }
    garbage_.store(decoder.skipped_bytes(), std::memory_order_relaxed);
    bad_frames_.store(decoder.bad_frames(), std::memory_order_relaxed);
  }
}

void Capture::take(protocol::SonarFrame frame, bool& ended) {
  CaptureItem item;
  if (auto* ping = std::get_if<protocol::SonarPing>(&frame)) {
    pings_.fetch_add(1, std::memory_order_relaxed);
    // Seqs count up per vehicle run; a step back is a new run, not a gap.
    if (last_seq_ && ping->seq > *last_seq_ + 1) {
      seq_gaps_.fetch_add(1, std::memory_order_relaxed);
      lost_pings_.fetch_add(ping->seq - *last_seq_ - 1, std::memory_order_relaxed);
    }
    last_seq_ = ping->seq;
    item.what = std::move(*ping);
  } else if (auto* status = std::get_if<protocol::SonarStatus>(&frame)) {
    item.what = *status;
  } else {
    item.what = std::move(std::get<protocol::SonarEnd>(frame));
    ended = true;
  }
  item.seq_gaps = seq_gaps_.load(std::memory_order_relaxed);
  item.lost_pings = lost_pings_.load(std::memory_order_relaxed);
  queue_.push(std::move(item));
}

}  // namespace strata::sonar
