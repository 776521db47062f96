// libFuzzer target: any bytes as a UDP datagram from an IMC peer. decode()
// must return a Packet or a Drop, never crash; what decodes must encode to
// the very same bytes (the codec keeps every field, and a payload with
// bytes left over is dropped), and those bytes must decode again to a
// packet that encodes the same. Anything else prints what broke and traps.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
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

void check(std::span<const std::uint8_t> bytes) {
  auto decoded = decode(bytes);
  if (const Drop* drop = std::get_if<Drop>(&decoded)) {
    if (*drop == Drop::Filtered) broken("decode says filtered", bytes);
    return;
  }
  const Packet& packet = std::get<Packet>(decoded);
  auto header = peek_header(bytes);
  if (!header || !(*header == packet.header)) broken("peek_header differs from the decoded header", bytes);
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

}  // namespace strata::imc::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  strata::imc::fuzz::check(std::span<const std::uint8_t>(data, size));
  return 0;
}
