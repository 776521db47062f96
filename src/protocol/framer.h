#pragma once
// Cuts a byte stream into lines. Bytes arrive in chunks of any size (a line
// may be split across chunks, a chunk may hold several lines); each complete
// line comes out once, without its "\n" or "\r\n". Memory stays bounded: a
// line longer than the framer's maximum (kMaxLineBytes unless given; the
// terminator included) is reported once, as soon as it is known to be too
// long, and its bytes are dropped through the next "\n". Not thread-safe; one
// framer per connection and direction.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "protocol/message.h"

namespace strata::protocol {

struct Frame {
  // A complete line (too_long false), or the first maximum - 1 bytes of
  // an overlong one (too_long true), kept so the receiver can read its id
  // with peek_id() and answer `err ID too_long`.
  std::string line;
  bool too_long = false;

  friend bool operator==(const Frame&, const Frame&) = default;
};

class LineFramer {
 public:
  // max_line_bytes: the longest line taken, its "\n" included (at least 2).
  explicit LineFramer(std::size_t max_line_bytes = kMaxLineBytes)
      : max_content_(max_line_bytes > 1 ? max_line_bytes - 1 : 1) {}

  // Returns the frames completed by these bytes, in order.
  std::vector<Frame> feed(std::string_view bytes);

  // Bytes of an unfinished line held back (never more than the maximum - 1).
  // At end of stream they are an incomplete line; the caller drops them.
  std::size_t pending_bytes() const { return discarding_ ? 0 : buffer_.size(); }
  // True while the rest of an overlong line is being dropped.
  bool discarding() const { return discarding_; }
  void reset();

 private:
  std::size_t max_content_;
  std::string buffer_;
  bool discarding_ = false;
};

}  // namespace strata::protocol
