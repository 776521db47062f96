// libFuzzer target: any bytes as a UDP datagram from an IMC peer. decode()
// must return a Packet or a Drop, never crash; what decodes must encode to
// the very same bytes (the codec keeps every field, and a payload with
// bytes left over is dropped), and those bytes must decode again to a
// packet that encodes the same. Each input also goes through with its size
// field and CRC made right, to reach the fields. Anything else prints what
// broke and traps.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <span>
#include <string_view>
#include <variant>
#include <vector>

#include "imc/codec.h"

namespace strata::imc::fuzz {

[[noreturn]] void broken(std::string_view what, std::span<const std::uint8_t> input) {
  std::fprintf(stderr, "imc_fuzz: %.*s\n  input (%zu bytes):", static_cast<int>(what.size()), what.data(),
               input.size());
  for (std::uint8_t b : input) std::fprintf(stderr, " %02x", static_cast<unsigned>(b));
  std::fprintf(stderr, "\n");
  __builtin_trap();
}

// Headers equal, the timestamp compared by its bits (it may be a NaN).
bool same_header(Header a, Header b) {
  if (std::memcmp(&a.timestamp, &b.timestamp, sizeof a.timestamp) != 0) return false;
  a.timestamp = b.timestamp = 0;
  return a == b;
}

void check(std::span<const std::uint8_t> bytes) {
  auto decoded = decode(bytes);
  if (const Drop* drop = std::get_if<Drop>(&decoded)) {
    if (*drop == Drop::Filtered) broken("decode says filtered", bytes);
    return;
  }
  const Packet& packet = std::get<Packet>(decoded);
  auto header = peek_header(bytes);
  if (!header || !same_header(*header, packet.header)) broken("peek_header differs from the decoded header", bytes);
  auto encoded = encode(packet);
  if (!encoded.ok()) broken("a decoded packet does not encode", bytes);
  const std::vector<std::uint8_t>& again = encoded.value();
  if (!std::equal(again.begin(), again.end(), bytes.begin(), bytes.end())) {
    broken("decode -> encode changed the bytes", bytes);
  }
  auto redecoded = decode(again);
  if (!std::holds_alternative<Packet>(redecoded)) broken("the re-encoded packet does not decode", bytes);
  auto reencoded = encode(std::get<Packet>(redecoded));
  if (!reencoded.ok() || reencoded.value() != again) broken("the second round trip changed the bytes", bytes);
}

// The same bytes with the size field and the CRC made to agree with them,
// so that mutations reach the fields rather than stopping at the CRC.
std::vector<std::uint8_t> made_consistent(std::span<const std::uint8_t> bytes) {
  std::vector<std::uint8_t> out(bytes.begin(), bytes.end() - kFooterBytes);
  const std::size_t size = out.size() - kHeaderBytes;
  out[4] = static_cast<std::uint8_t>(size & 0xFF);
  out[5] = static_cast<std::uint8_t>((size >> 8) & 0xFF);
  std::uint16_t crc = 0;
  for (std::uint8_t b : out) {
    crc = static_cast<std::uint16_t>(crc ^ b);
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 1u) ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001u) : static_cast<std::uint16_t>(crc >> 1);
    }
  }
  out.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  out.push_back(static_cast<std::uint8_t>(crc >> 8));
  return out;
}

}  // namespace strata::imc::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace strata::imc;
  const std::span<const std::uint8_t> bytes(data, size);
  fuzz::check(bytes);
  if (size >= kHeaderBytes + kFooterBytes && size <= kMaxPacketBytes) fuzz::check(fuzz::made_consistent(bytes));
  return 0;
}
