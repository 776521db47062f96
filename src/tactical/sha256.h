#pragma once
// SHA-256 (FIPS 180-4), for the mission log's run header: a stable digest of
// the mission and data files, so a log says exactly which inputs made it.
// Not used for security.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/result.h"

namespace strata::tactical {

class Sha256 {
 public:
  using Digest = std::array<std::uint8_t, 32>;
  // Best: the CPU's SHA extensions when it has them (x86-64 SHA-NI, about
  // five times faster: the precompiled PROLOG driver is hashed at every
  // start), else the portable code. Portable: the portable code always.
  enum class Code { Best, Portable };

  explicit Sha256(Code code = Code::Best);
  // Whether Code::Best uses the CPU's SHA extensions on this machine.
  static bool cpu_extensions();
  void update(std::string_view bytes);
  // Pads and returns the digest; the object must not be updated afterwards.
  Digest finish();

  static std::string hex(const Digest& digest);

 private:
  void compress(const std::uint8_t* block);

  std::array<std::uint32_t, 8> h_;
  bool extensions_;
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t length_ = 0;  // bytes so far
  bool finished_ = false;
};

// Lower-case hex digest of bytes.
std::string sha256_hex(std::string_view bytes);
// Lower-case hex digest of a regular file's bytes (core::read_regular_file),
// or an Io error (Overflow past max_bytes).
core::Result<std::string> sha256_file(const std::string& path, std::size_t max_bytes = std::size_t{256} << 20);

}  // namespace strata::tactical
