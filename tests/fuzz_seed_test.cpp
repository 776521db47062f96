// Replays every seed of a fuzz corpus through its fuzz target, so a crash
// found once stays fixed in every ordinary build. Built once per target
// (each defines LLVMFuzzerTestOneInput): STRATA_FUZZ_CORPUS names the folder
// under fuzz/corpus/, STRATA_MIN_SEEDS how many seeds it must hold.
// STRATA_FUZZ_SHIPPED, when defined, is an extension (".pl", ".coral"):
// the shipped missions of that language (missions/) are seeds too, read
// where they are; the committed corpus holds no copy of one, which would
// drift from it (fuzz/seed-corpus seeds a libFuzzer run the same way).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The committed seeds, in fuzz/corpus/.
std::vector<std::string> committed() {
  std::vector<std::string> out;
  fs::path dir = fs::path(STRATA_SOURCE_DIR) / "fuzz" / "corpus" / STRATA_FUZZ_CORPUS;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file()) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The shipped missions that are seeds of this target, where they are.
std::vector<std::string> shipped() {
  std::vector<std::string> out;
#ifdef STRATA_FUZZ_SHIPPED
  for (const auto& e : fs::recursive_directory_iterator(fs::path(STRATA_SOURCE_DIR) / "missions")) {
    if (e.is_regular_file() && e.path().extension() == STRATA_FUZZ_SHIPPED) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
#endif
  return out;
}

std::vector<std::string> seeds() {
  std::vector<std::string> out = committed();
  for (auto& path : shipped()) out.push_back(std::move(path));
  return out;
}

TEST(FuzzSeeds, CorpusIsNotEmpty) { EXPECT_GE(seeds().size(), std::size_t{STRATA_MIN_SEEDS}); }

#ifdef STRATA_FUZZ_SHIPPED
TEST(FuzzSeeds, ShippedMissionsAreSeedsWithoutCopies) {
  EXPECT_FALSE(shipped().empty()) << "no shipped mission ends in " << STRATA_FUZZ_SHIPPED;
  for (const auto& mission : shipped()) {
    const std::string text = bytes_of(mission);
    for (const auto& seed : committed()) {
      EXPECT_NE(text, bytes_of(seed)) << seed << " is a copy of " << mission
                                      << ": the shipped missions are seeds where they are";
    }
  }
}
#endif

TEST(FuzzSeeds, EverySeedRunsThroughTheTarget) {
  for (const auto& path : seeds()) {
    const std::string bytes = bytes_of(path);
    SCOPED_TRACE(path);
    EXPECT_EQ(0, LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
  }
}

}  // namespace
