// The deadlock question (petri/question.h) on each net of ../shared/pnml
// (when present) and on two generated families, beside the full exploration
// of the same net and LoLA 2's figures from lola-deadlock.csv:
//
//   deadlock/MODEL/explore      explore(), liveness off: every marking
//   deadlock/MODEL/reduced      answer_question(), stubborn sets
//   deadlock/MODEL/unreduced    answer_question(), reduction = false
//
// Counters: ms (wall time of one run, parsing excluded), cpu_ms (the
// process's CPU time for it: steadier on a loaded machine), markings (visited
// or, for explore, reachable), edges (transitions fired), answer (1 yes, 0
// no, -1 not decided), and on
// every row lola_ms and lola_markings (LoLA 2's question time and markings
// visited, measured on this class of machine; -1 when not listed).
// Run: ./bench/question_bench --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "petri/explorer.h"
#include "petri/net_families.h"
#include "petri/pnml.h"
#include "petri/question.h"

namespace strata::petri {
namespace {

namespace fs = std::filesystem;

const fs::path kQuestionCorpus = fs::path(STRATA_SOURCE_DIR) / ".." / "shared" / "pnml";

struct LolaFigures {
  double ms = -1;
  double markings = -1;
};

std::map<std::string, LolaFigures> lola_figures() {
  std::map<std::string, LolaFigures> out;
  std::ifstream in(kQuestionCorpus / "lola-deadlock.csv");
  std::string line;
  std::getline(in, line);  // model,states,deadlock,lola_question_s,lola_markings_visited,...
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) c.push_back(cell);
    if (c.size() >= 5) out[c[0]] = {std::stod(c[3]) * 1000, std::stod(c[4])};
  }
  return out;
}

std::vector<std::string> corpus_in_order() {
  std::vector<std::string> out;
  std::ifstream in(kQuestionCorpus / "answers.csv");
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) out.push_back(line.substr(0, line.find(',')));
  return out;
}

enum class Mode { Explore, Reduced, Unreduced };

void bm_deadlock(benchmark::State& st, const std::shared_ptr<const Net>& net, Mode mode, LolaFigures lola) {
  double seconds = 0, cpu_seconds = 0, markings = 0, answer = -1, edges = 0;
  Question q;
  q.kind = QuestionKind::Deadlock;
  for (auto _ : st) {
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpu_start = std::clock();
    if (mode == Mode::Explore) {
      ExploreOptions o;
      o.liveness = false;
      const ExploreResult r = explore(*net, o);
      markings = static_cast<double>(r.states);
      edges = static_cast<double>(r.edges);
      answer = r.complete ? (r.deadlock ? 1 : 0) : -1;
    } else {
      QuestionOptions o;
      o.reduction = mode == Mode::Reduced;
      const QuestionResult r = answer_question(*net, q, o);
      markings = static_cast<double>(r.states);
      edges = static_cast<double>(r.edges);
      answer = r.answer == Answer::Yes ? 1 : r.answer == Answer::No ? 0 : -1;
    }
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    cpu_seconds = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  }
  st.counters["ms"] = seconds * 1000;
  st.counters["cpu_ms"] = cpu_seconds * 1000;
  st.counters["markings"] = markings;
  st.counters["edges"] = edges;
  st.counters["answer"] = answer;
  st.counters["lola_ms"] = lola.ms;
  st.counters["lola_markings"] = lola.markings;
}

void register_net(const std::string& name, const std::shared_ptr<const Net>& net, LolaFigures lola) {
  static const std::pair<const char*, Mode> kModes[] = {
      {"explore", Mode::Explore}, {"reduced", Mode::Reduced}, {"unreduced", Mode::Unreduced}};
  for (const auto& [label, mode] : kModes) {
    benchmark::RegisterBenchmark(("deadlock/" + name + "/" + label).c_str(), bm_deadlock, net, mode, lola)
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1);
  }
}

void register_all() {
  const auto lola = lola_figures();
  for (const std::string& model : corpus_in_order()) {
    auto loaded = read_pnml((kQuestionCorpus / model / "model.pnml").string());
    if (!loaded) continue;
    auto it = lola.find(model);
    register_net(model, std::make_shared<const Net>(std::move(loaded).value().net),
                 it == lola.end() ? LolaFigures{} : it->second);
  }
  register_net("philosophers-12", std::make_shared<const Net>(dining_philosophers(12)), {});
  register_net("referendum-12", std::make_shared<const Net>(referendum(12)), {});
}

}  // namespace
}  // namespace strata::petri

int main(int argc, char** argv) {
  strata::petri::register_all();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
