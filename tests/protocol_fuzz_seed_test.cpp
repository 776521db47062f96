// Replays every seed of the protocol fuzz corpus through the protocol fuzz
// target (fuzz/protocol_fuzz.cpp, linked into this executable alone: each
// target defines LLVMFuzzerTestOneInput), so a crash or a round-trip break
// found once stays fixed in every ordinary build.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;

std::vector<std::string> seeds() {
  std::vector<std::string> out;
  fs::path dir = fs::path(STRATA_SOURCE_DIR) / "fuzz" / "corpus" / "protocol";
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file()) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(ProtocolFuzzSeeds, CorpusIsNotEmpty) { EXPECT_GE(seeds().size(), 10u); }

TEST(ProtocolFuzzSeeds, EverySeedRunsThroughTheTarget) {
  for (const auto& path : seeds()) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    std::string bytes = ss.str();
    SCOPED_TRACE(path);
    EXPECT_EQ(0, LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()),
                                        bytes.size()));
  }
}

}  // namespace
