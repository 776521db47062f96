#include "protocol/framer.h"

namespace strata::protocol {

std::vector<Frame> LineFramer::feed(std::string_view bytes) {
  std::vector<Frame> frames;
  while (!bytes.empty()) {
    std::size_t nl = bytes.find('\n');
    std::string_view part = bytes.substr(0, nl);
    if (discarding_) {
      if (nl == std::string_view::npos) return frames;
      discarding_ = false;
      bytes.remove_prefix(nl + 1);
      continue;
    }
    // A line of n bytes before its "\n" takes n + 1 bytes on the wire (a
    // "\r" before the "\n" is one of the n), so at most the maximum - 1 are
    // kept; one more byte that is not the "\n" makes the line too long.
    if (buffer_.size() + part.size() > max_content_) {
      buffer_.append(part.substr(0, max_content_ - buffer_.size()));
      frames.push_back(Frame{std::move(buffer_), true});
      buffer_.clear();
      discarding_ = true;
      bytes.remove_prefix(part.size());  // the "\n", if any, ends the discarding
      continue;
    }
    buffer_.append(part);
    if (nl == std::string_view::npos) return frames;
    if (!buffer_.empty() && buffer_.back() == '\r') buffer_.pop_back();
    frames.push_back(Frame{std::move(buffer_), false});
    buffer_.clear();
    bytes.remove_prefix(nl + 1);
  }
  return frames;
}

void LineFramer::reset() {
  buffer_.clear();
  discarding_ = false;
}

}  // namespace strata::protocol
