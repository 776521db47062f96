#pragma once
// IMC packets: encode and decode, for UDP datagrams (one packet each).
//
// A packet is a 20-byte header (sync 0xFE54, mgid, size, timestamp, src,
// src_ent, dst, dst_ent), the message's payload (`size` bytes) and a
// CRC-16-IBM (polynomial 0xA001 reflected, initial 0) of header and
// payload, all little-endian. Only the messages of messages.def decode;
// anything else is dropped with a reason (Drop), never thrown, and
// decoding allocates nothing larger than the datagram. Thread-safe: no
// state.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "core/result.h"
#include "imc/message.h"

namespace strata::imc {

struct Header {
  std::uint16_t mgid = 0;
  std::uint16_t size = 0;  // payload bytes
  double timestamp = 0;    // s (the sender's clock; DUNE: since the epoch)
  std::uint16_t src = 0;
  std::uint8_t src_ent = 0;
  std::uint16_t dst = kNullId;
  std::uint8_t dst_ent = kAnyEntity;
  friend bool operator==(const Header&, const Header&) = default;
};

struct Packet {
  Header header;
  Message message;
  friend bool operator==(const Packet&, const Packet&) = default;
};

// The largest packet, header and CRC included (the size a UDP datagram
// can carry, and what `size` can describe).
inline constexpr std::size_t kMaxPacketBytes = 65535;

// The datagram for `packet`: header.mgid and header.size are set from the
// message, sync and CRC added. InvalidInput only for what cannot be
// encoded: a text, rawdata or list over 65535 (bytes or elements), inline
// messages nested deeper than kMaxDepth, a packet over kMaxPacketBytes.
core::Result<std::vector<std::uint8_t>> encode(const Packet& packet);

// Why a datagram was not decoded.
enum class Drop : std::uint8_t {
  Truncated,  // shorter than a header and CRC, or than its size field says
  BadSync,    // not 0xFE54 (another IMC version, or not IMC)
  BadSize,    // longer than its size field says, or than kMaxPacketBytes
  BadCrc,     // the CRC does not match
  UnknownId,  // a message (the packet's or an inline one) not in messages.def
  BadField,   // a field runs past the payload, bytes left after the last field,
              // a list's count larger than its bytes allow, an inline message
              // of the wrong type (Reference.speed not a DesiredSpeed)
  TooDeep,    // inline messages nested deeper than kMaxDepth, or more than
              // kMaxInlineMessages of them in one packet
  Filtered,   // not decoded on purpose (the caller's filter; decode never says it)
};
inline constexpr std::size_t kDropReasons = 8;
// "truncated", "bad_sync", "bad_size", "bad_crc", "unknown_id", "bad_field",
// "too_deep", "filtered".
std::string_view drop_name(Drop d);

// The header alone (the first 20 bytes, sync checked; size and CRC are
// not): for filtering by mgid or source before decoding.
std::optional<Header> peek_header(std::span<const std::uint8_t> datagram);

// The whole datagram: sync, size == datagram length - 22, CRC, every field;
// nested inline messages at most kMaxDepth deep; a list's count bounded by
// the bytes left. Anything else is a Drop.
std::variant<Packet, Drop> decode(std::span<const std::uint8_t> datagram);

// Counts of what was dropped, per reason.
struct DropCounts {
  std::array<std::uint64_t, kDropReasons> by_reason{};
  std::uint64_t total() const;
  void add(Drop d);
  // The reasons that occurred, most frequent first ("3 bad_crc, 1
  // truncated"); "none" when nothing was dropped.
  std::string summary() const;
};

}  // namespace strata::imc
