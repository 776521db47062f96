#include "petri/packed_markings.h"

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace strata::petri::packed {
namespace {

constexpr Tokens kWide = 0xFFFFFFFFu;

// Five places as wide as 32 bits (their initial tokens; no P-semiflow is
// asked for): three words a marking.
Net wide_net() {
  NetBuilder b;
  for (int i = 0; i < 5; ++i) b.add_place("p" + std::to_string(i), kWide);
  return std::move(b).build();
}

// The i-th of a family of distinct markings of wide_net().
std::vector<Tokens> marking(std::uint32_t i) { return {i, i * 7u, i ^ 0x5555u, i * 13u + 1u, ~i}; }

bool insert(PackedMarkings& set, std::uint32_t i) {
  std::vector<std::uint64_t> m(set.words());
  set.pack(marking(i), m.data());
  return set.insert(m.data());
}

bool contains(const PackedMarkings& set, std::uint32_t i) {
  std::vector<std::uint64_t> m(set.words());
  set.pack(marking(i), m.data());
  return set.contains(m.data());
}

// A field of /proc/self/status in kB, or -1.
long status_kb(const std::string& key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key + ":", 0) == 0) return std::stol(line.substr(key.size() + 1));
  }
  return -1;
}

TEST(PackedMarkings, EveryMarkingIsFoundAfterTheTableGrowsInPlace) {
  // 700,000 markings of 3 words: the table grows past 2 MB, where the old
  // array is given back while the new one fills (grow()), three times.
  PackedMarkings set;
  set.start(wide_net(), false);
  ASSERT_EQ(3u, set.words());
  constexpr std::uint32_t kCount = 700'000;
  for (std::uint32_t i = 0; i < kCount; ++i) ASSERT_TRUE(insert(set, i)) << i;
  EXPECT_EQ(kCount, set.size());
  EXPECT_EQ((std::size_t{1} << 20) * 24, set.table_bytes());
  for (std::uint32_t i = 0; i < kCount; ++i) ASSERT_TRUE(contains(set, i)) << i;
  for (std::uint32_t i = 0; i < kCount; i += 97) ASSERT_FALSE(insert(set, i)) << i;
  for (std::uint32_t i = kCount; i < kCount + 10'000; ++i) ASSERT_FALSE(contains(set, i)) << i;
  EXPECT_EQ(kCount, set.size());
}

TEST(PackedMarkings, AGrowingTableIsNotHeldTwice) {
  // The doubling from 12 MB to 24 MB (at 393,217 markings). Holding both
  // arrays, as the table did before, raises the peak resident memory by the
  // whole new array; sweeping gives the old one back as the new fills.
  PackedMarkings set;
  set.start(wide_net(), false);
  constexpr std::uint32_t kBeforeGrowth = (std::uint32_t{1} << 19) / 4 * 3;
  for (std::uint32_t i = 0; i < kBeforeGrowth; ++i) ASSERT_TRUE(insert(set, i));
  const std::size_t old_bytes = set.table_bytes();
  ASSERT_EQ(std::size_t{12} << 20, old_bytes);
  // The counted peak.
  EXPECT_LE(set.bytes_after_insert(), 2 * old_bytes + 2 * Words::kHuge);
  // The resident peak: Linux resets VmHWM on writing 5 to clear_refs.
  const long rss_kb = status_kb("VmRSS");
  std::ofstream clear("/proc/self/clear_refs");
  if (!(clear << "5" << std::flush) || rss_kb < 0) GTEST_SKIP() << "cannot reset the peak RSS (/proc/self/clear_refs)";
  clear.close();
  ASSERT_TRUE(insert(set, kBeforeGrowth));
  const long grew_kb = status_kb("VmHWM") - rss_kb;
  ASSERT_EQ(2 * old_bytes, set.table_bytes());
  EXPECT_LE(set.peak_table_bytes(), 2 * old_bytes + 2 * Words::kHuge);
  // Holding both: + 24 MB. Sweeping: + 12 MB and a few pages.
  EXPECT_LT(grew_kb, static_cast<long>((old_bytes + (std::size_t{4} << 20)) >> 10))
      << "the peak RSS grew by " << grew_kb << " kB for a table grown from " << (old_bytes >> 10) << " kB";
  for (std::uint32_t i = 0; i <= kBeforeGrowth; i += 7) ASSERT_TRUE(contains(set, i)) << i;
}

}  // namespace
}  // namespace strata::petri::packed
