#pragma once
// For tests: the corpus of P/T nets with known answers in ../shared/pnml
// beside the source folder (answers.csv, one row per net, read by its
// header). The folder is not part of a clone: tests that use it skip, saying
// so, when it is absent. Needs STRATA_SOURCE_DIR defined by the test target.
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace strata::petri::corpus {

inline const std::filesystem::path kCorpusDir = std::filesystem::path(STRATA_SOURCE_DIR) / ".." / "shared" / "pnml";

inline bool corpus_present() { return std::filesystem::exists(kCorpusDir / "answers.csv"); }

struct CorpusAnswer {
  std::string model;
  std::map<std::string, std::string> values;  // column -> text
  std::uint64_t number(const std::string& column) const { return std::stoull(values.at(column)); }
  bool verdict(const std::string& column) const { return values.at(column) == "TRUE"; }
  std::filesystem::path pnml() const { return kCorpusDir / model / "model.pnml"; }
};

// Every row of answers.csv, read once (none when the folder is absent).
inline const std::vector<CorpusAnswer>& corpus_answers() {
  static const std::vector<CorpusAnswer> all = [] {
    std::vector<CorpusAnswer> out;
    if (!corpus_present()) return out;
    std::ifstream in(kCorpusDir / "answers.csv");
    auto split = [](const std::string& s) {
      std::vector<std::string> cells;
      std::stringstream ss(s);
      for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
      return cells;
    };
    std::string line;
    if (!std::getline(in, line)) return out;
    const std::vector<std::string> header = split(line);
    while (std::getline(in, line)) {
      const std::vector<std::string> cells = split(line);
      if (cells.size() != header.size()) continue;
      CorpusAnswer a{cells[0], {}};
      for (std::size_t i = 0; i < header.size(); ++i) a.values[header[i]] = cells[i];
      out.push_back(std::move(a));
    }
    return out;
  }();
  return all;
}

// The row of `model`, or nullptr.
inline const CorpusAnswer* corpus_answer(const std::string& model) {
  for (const CorpusAnswer& a : corpus_answers()) {
    if (a.model == model) return &a;
  }
  return nullptr;
}

// Parameters for a TEST_P over the corpus: the model names, or one
// "absent" (a test that skips) when the folder is not there.
inline std::vector<std::string> corpus_model_names() {
  std::vector<std::string> names;
  for (const CorpusAnswer& a : corpus_answers()) names.push_back(a.model);
  if (names.empty()) names.emplace_back("absent");
  return names;
}

// A test name from a model name (gtest allows [A-Za-z0-9_] only).
inline std::string corpus_test_name(const ::testing::TestParamInfo<std::string>& p) {
  std::string name = p.param;
  for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return name;
}

}  // namespace strata::petri::corpus
