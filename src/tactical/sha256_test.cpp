#include "tactical/sha256.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace strata::tactical {
namespace {

// FIPS 180-2 appendix B and the NIST example values.
TEST(Sha256, KnownVectors) {
  EXPECT_EQ("e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855", sha256_hex(""));
  EXPECT_EQ("ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad", sha256_hex("abc"));
  EXPECT_EQ("248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1",
            sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"));
  EXPECT_EQ("cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1",
            sha256_hex("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmnopq"
                       "klmnopqrlmnopqrsmnopqrstnopqrstu"));
  EXPECT_EQ("cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0", sha256_hex(std::string(1000000, 'a')));
}

TEST(Sha256, PaddingBoundaries) {
  // 55, 56 and 64 bytes straddle the one-block / two-block padding edge.
  EXPECT_EQ("9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318", sha256_hex(std::string(55, 'a')));
  EXPECT_EQ("b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a", sha256_hex(std::string(56, 'a')));
  EXPECT_EQ("ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb", sha256_hex(std::string(64, 'a')));
}

TEST(Sha256, PiecesGiveTheSameDigestAsTheWhole) {
  std::string text;
  for (int i = 0; i < 300; ++i) text += static_cast<char>('a' + i % 26);
  const std::string whole = sha256_hex(text);
  for (std::size_t step : {1u, 3u, 63u, 64u, 65u, 127u}) {
    Sha256 s;
    for (std::size_t i = 0; i < text.size(); i += step) s.update(std::string_view(text).substr(i, step));
    EXPECT_EQ(whole, Sha256::hex(s.finish())) << step;
  }
}

// The CPU's SHA extensions, where this machine has them, and the portable
// code give the same digests at every length up to three blocks and past.
TEST(Sha256, CpuExtensionsAndPortableCodeAgree) {
  if (!Sha256::cpu_extensions()) GTEST_SKIP() << "this CPU has no SHA extensions";
  std::string text;
  for (int i = 0; i < 300; ++i) text += static_cast<char>((i * 131 + 7) % 256);
  for (std::size_t n = 0; n <= text.size(); ++n) {
    Sha256 best;
    Sha256 portable(Sha256::Code::Portable);
    best.update(std::string_view(text).substr(0, n));
    portable.update(std::string_view(text).substr(0, n));
    ASSERT_EQ(Sha256::hex(portable.finish()), Sha256::hex(best.finish())) << n;
  }
}

TEST(Sha256, Files) {
  auto path = std::filesystem::temp_directory_path() / ("strata_sha256_" + std::to_string(::getpid()));
  {
    std::ofstream out(path, std::ios::binary);
    out << "abc";
  }
  auto digest = sha256_file(path.string());
  std::filesystem::remove(path);
  ASSERT_TRUE(digest.ok());
  EXPECT_EQ("ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad", digest.value());
  auto missing = sha256_file(path.string());
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(core::ErrorCode::Io, missing.error().code);
}

}  // namespace
}  // namespace strata::tactical
