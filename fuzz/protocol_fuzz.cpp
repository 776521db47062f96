// libFuzzer target: any bytes as what arrives on one side of the link.
// They go through the line framer whole and in chunk splits derived from the
// first byte (every split must give the same frames and end state), then
// every frame through both decoders. Whatever decodes is encoded again: the
// line must be one line, and decoding it must give the same value back. A
// line that does not decode becomes the `err` the vehicle would answer
// (to_err), which must survive the same round trip, as the client reads it.
//
// What the encoder is documented to change is allowed, and only that: free
// text (err MESSAGE, event TEXT) with its unprintable bytes as '?' and cut to
// fit the line, ending "..."; and a value whose canonical line is longer than
// kMaxLineBytes (floats are written in full: `1e9` comes back as
// `1000000000.0`) must then be refused as too_long. Anything else is a bug:
// the target prints what broke and traps.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "protocol/codec.h"
#include "protocol/fields.h"
#include "protocol/framer.h"
#include "protocol/message.h"

namespace strata::protocol {
namespace {

// The bytes with \r, \n and other unprintable bytes as C escapes.
std::string visible(std::string_view bytes) {
  std::string out;
  for (char c : bytes) {
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c >= 0x20 && c <= 0x7e) {
      out += c;
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += hex;
    }
  }
  return out;
}

[[noreturn]] void broken(std::string_view what, std::string_view input, std::string_view output) {
  std::fprintf(stderr, "protocol_fuzz: %.*s\n  input:  [%s]\n  output: [%s]\n", static_cast<int>(what.size()),
               what.data(), visible(input).c_str(), visible(output).c_str());
  __builtin_trap();
}

void require(bool ok, std::string_view what, std::string_view input, std::string_view output = {}) {
  if (!ok) broken(what, input, output);
}

// ---- framing ------------------------------------------------------------------

struct Framed {
  std::vector<Frame> frames;
  std::size_t pending_bytes = 0;
  bool discarding = false;
  friend bool operator==(const Framed&, const Framed&) = default;
};

// Feeds bytes in chunks whose sizes next_size() gives (each >= 1).
template <typename NextSize>
Framed frame_in_chunks(std::string_view bytes, NextSize next_size) {
  LineFramer framer;
  Framed out;
  while (!bytes.empty()) {
    std::size_t n = std::min(bytes.size(), next_size());
    for (Frame& f : framer.feed(bytes.substr(0, n))) out.frames.push_back(std::move(f));
    bytes.remove_prefix(n);
  }
  out.pending_bytes = framer.pending_bytes();
  out.discarding = framer.discarding();
  return out;
}

Framed frame_all(std::string_view bytes) {
  LineFramer framer;
  Framed out{framer.feed(bytes), framer.pending_bytes(), framer.discarding()};
  return out;
}

// ---- round trips --------------------------------------------------------------

// What the encoder makes of free text: bytes the grammar cannot carry as '?'.
std::string printable_text(std::string_view text) {
  std::string out(text);
  for (char& c : out) {
    bool printable = c >= 0x20 && c <= 0x7e;
    if (!printable && c != '\n' && c != '\t') c = '?';
  }
  return out;
}

std::string* free_text(VehicleMessage& m) {
  if (auto* e = std::get_if<Err>(&m)) return &e->message;
  if (auto* e = std::get_if<Event>(&m)) return &e->text;
  return nullptr;
}

// `after` is `before` as the encoder may write it: '?' for unprintable bytes,
// and possibly cut, ending "...".
bool is_text_as_encoded(std::string_view before, std::string_view after) {
  std::string expected = printable_text(before);
  if (after == expected) return true;
  constexpr std::string_view kEllipsis = "...";
  if (after.size() < kEllipsis.size() || !after.ends_with(kEllipsis)) return false;
  std::string_view kept = after.substr(0, after.size() - kEllipsis.size());
  return kept.size() < expected.size() && std::string_view(expected).starts_with(kept);
}

void require_one_line(const std::string& line, std::string_view input) {
  require(!line.empty() && line.back() == '\n', "encoding does not end in \\n", input, line);
  require(line.find('\n') == line.size() - 1, "encoding holds more than one \\n", input, line);
}

void check_round_trip(const Request& r, std::string_view input) {
  std::string line = encode(r);
  require_one_line(line, input);
  auto again = decode_request(line);
  if (line.size() > kMaxLineBytes) {
    require(!again.ok() && again.error().code == ErrorCode::TooLong,
            "request encoded over kMaxLineBytes is not refused as too_long", input, line);
    return;
  }
  require(again.ok(), "encoded request does not decode", input, line);
  require(again.value() == r, "request changed in encode -> decode", input, line);
  require(encode(again.value()) == line, "request encoding is not stable", input, line);
}

void check_round_trip(const VehicleMessage& m, std::string_view input) {
  std::string line = encode(m);
  require_one_line(line, input);
  auto again = decode_vehicle_message(line);
  if (line.size() > kMaxLineBytes) {
    require(!again.ok() && again.error().code == ErrorCode::TooLong,
            "vehicle message encoded over kMaxLineBytes is not refused as too_long", input, line);
    return;
  }
  require(again.ok(), "encoded vehicle message does not decode", input, line);
  VehicleMessage& back = again.value();
  require(encode(back) == line, "vehicle message encoding is not stable", input, line);
  if (back == m) return;
  // Only the free text may differ, and only as the encoder documents.
  VehicleMessage expected = m;
  std::string* before = free_text(expected);
  const std::string* after = free_text(back);
  require(before != nullptr && after != nullptr, "vehicle message changed in encode -> decode", input, line);
  require(is_text_as_encoded(*before, *after), "free text changed beyond '?' and cutting", input, line);
  *before = *after;
  require(expected == back, "vehicle message changed in encode -> decode", input, line);
}

// The err line the vehicle would answer, as the client decodes it.
void check_error_reply(const DecodeError& e, std::string_view input) {
  require(e.id <= kMaxRequestId, "decode error carries an id over kMaxRequestId", input);
  require(!e.message.empty(), "decode error without a message", input);
  check_round_trip(VehicleMessage{to_err(e)}, input);
}

void check_frame(const Frame& frame) {
  std::string_view line = frame.line;
  require(line.find('\n') == std::string_view::npos, "frame holds a \\n", line);
  if (frame.too_long) {
    require(line.size() == kMaxLineBytes - 1, "too_long frame is not kMaxLineBytes - 1 bytes", line);
    check_round_trip(VehicleMessage{Err{peek_id(line), ErrorCode::TooLong, "line over 1024 bytes"}}, line);
    return;
  }
  require(line.size() < kMaxLineBytes, "frame longer than kMaxLineBytes - 1", line);

  auto request = decode_request(line);
  if (request.ok()) {
    check_round_trip(request.value(), line);
  } else {
    check_error_reply(request.error(), line);
  }
  // The decoder takes the line with or without its terminator alike, up to
  // kMaxLineBytes with it. (A frame may still end in "\r" when its line ended
  // "\r\r\n"; with a "\n" after it, that "\r" would join the terminator.)
  if (!line.ends_with('\r')) {
    for (std::string_view terminator : {std::string_view("\n"), std::string_view("\r\n")}) {
      std::string terminated = std::string(line) + std::string(terminator);
      auto again = decode_request(terminated);
      if (terminated.size() > kMaxLineBytes) {
        require(!again.ok() && again.error().code == ErrorCode::TooLong,
                "line over kMaxLineBytes with its terminator is not too_long", terminated);
        continue;
      }
      require(again.ok() == request.ok(), "the terminator changes whether a request decodes", terminated);
      if (request.ok()) {
        require(again.value() == request.value(), "the terminator changes the decoded request", terminated);
      } else {
        require(again.error().code == request.error().code && again.error().id == request.error().id,
                "the terminator changes the decode error", terminated);
      }
    }
  }

  auto message = decode_vehicle_message(line);
  if (message.ok()) {
    check_round_trip(message.value(), line);
  } else {
    check_error_reply(message.error(), line);
  }
}

}  // namespace
}  // namespace strata::protocol

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace strata::protocol;
  std::string_view bytes(reinterpret_cast<const char*>(data), size);
  if (bytes.empty()) return 0;
  const auto b = static_cast<std::uint8_t>(bytes[0]);

  Framed whole = frame_all(bytes);
  const std::size_t fixed = (b % 16u) + 1;
  Framed in_fixed = frame_in_chunks(bytes, [&] { return fixed; });
  // Sizes 1 .. kMaxLineBytes + 63 from a xorshift seeded by the first byte,
  // so that chunk ends fall on both sides of the too-long boundary.
  std::uint32_t state = 0x9e3779b9u ^ (std::uint32_t{b} * 0x01000193u);
  Framed in_random = frame_in_chunks(bytes, [&] {
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    std::uint32_t range = (b & 1u) ? 64u : static_cast<std::uint32_t>(kMaxLineBytes) + 64u;
    return std::size_t{state % range} + 1;
  });
  Framed bytewise = frame_in_chunks(bytes, [] { return std::size_t{1}; });
  require(in_fixed == whole, "fixed-size chunks give other frames", bytes);
  require(in_random == whole, "random chunks give other frames", bytes);
  require(bytewise == whole, "byte-by-byte feeding gives other frames", bytes);
  require(whole.pending_bytes < kMaxLineBytes, "framer holds kMaxLineBytes or more", bytes);

  for (const Frame& frame : whole.frames) check_frame(frame);
  return 0;
}
