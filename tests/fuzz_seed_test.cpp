// Replays every seed of a fuzz corpus through its fuzz target, so a crash
// found once stays fixed in every ordinary build. Built once per target
// (each defines LLVMFuzzerTestOneInput): STRATA_FUZZ_CORPUS names the folder
// under fuzz/corpus/, STRATA_MIN_SEEDS how many seeds it must hold.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;

std::vector<std::string> seeds() {
  std::vector<std::string> out;
  fs::path dir = fs::path(STRATA_SOURCE_DIR) / "fuzz" / "corpus" / STRATA_FUZZ_CORPUS;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file()) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(FuzzSeeds, CorpusIsNotEmpty) { EXPECT_GE(seeds().size(), std::size_t{STRATA_MIN_SEEDS}); }

TEST(FuzzSeeds, EverySeedRunsThroughTheTarget) {
  for (const auto& path : seeds()) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    std::string bytes = ss.str();
    SCOPED_TRACE(path);
    EXPECT_EQ(0, LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
  }
}

}  // namespace
