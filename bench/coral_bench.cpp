// Front-end throughput on a generated mission: one file holding a mission
// and the phase nets it runs, n transitions in all.
//   coral/load          lex + parse (coral::load)
//   coral/compile_file  lex + parse + check + compile to petri::Net
//   coral/compile_file_reversed_chain
//                       one mission whose n transitions form a chain
//                       s0 -> s1 -> ... declared last link first: the order
//                       the checker's never-enabled fixpoint handles worst
//                       (one pass per link), kept to track that cost
// bytes_per_second is source text; transitions_per_second counts every
// transition of the load. The text is compiled once before timing; a load
// that does not compile cleanly is skipped with its first error.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "coral/compiler.h"
#include "coral/loader.h"
#include "core/diagnostic.h"
#include "core/source.h"

namespace strata::coral {
namespace {

constexpr std::size_t kTransitionsPerPhase = 500;
constexpr const char* kFileName = "gen.coral";

struct Generated {
  std::string text;
  std::size_t transitions = 0;
};

// Appends a phase net with exactly k transitions (k >= 1): a pipeline of
// stages s0 -> s1 -> ... that cycles through EXEC, ASK with a retry loop,
// weighted signals over a shared resource place, REPORT with an EXEC carrying
// arguments, and an ASK that can abort. Its exits are (complete, abort).
void append_phase(std::string& out, std::size_t index, std::size_t k) {
  std::string body;
  std::vector<std::string> places;
  bool uses_ready = false;
  bool uses_abort = false;
  std::size_t j = 0;
  std::uint32_t w = 1;  // tokens the previous stage put on s{j}
  auto wait_stage = [&] { return w == 1 ? fmt::format("s{}", j) : fmt::format("s{}*{}", j, w); };
  for (std::size_t left = k - 1; left > 0; ++j) {
    places.push_back(fmt::format("s{}", j));
    std::size_t pattern = j % 5;
    if (pattern == 1 && left < 2) pattern = 0;
    switch (pattern) {
      case 0:
        fmt::format_to(std::back_inserter(body),
                       "  transition t{0} priority 1 {{\n"
                       "    wait   {{ {1} }}\n"
                       "    action {{ TACTIC(EXEC, next_setpt_data, s{2}) }}\n"
                       "  }}\n",
                       j, wait_stage(), j + 1);
        w = 1;
        left -= 1;
        break;
      case 1:
        fmt::format_to(std::back_inserter(body),
                       "  transition t{0} {{\n"
                       "    wait   {{ {1} }}\n"
                       "    action {{ TACTIC(ASK, depth_reached, s{2}, r{0}) }}\n"
                       "  }}\n"
                       "  transition u{0} {{\n"
                       "    wait   {{ r{0} }}\n"
                       "    action {{ TACTIC(REPORT, \"stage {0}: depth not reached, retrying\") }}"
                       "\n"
                       "    signal {{ {1} }}\n"
                       "  }}\n",
                       j, wait_stage(), j + 1);
        places.push_back(fmt::format("r{}", j));
        w = 1;
        left -= 2;
        break;
      case 2:
        fmt::format_to(std::back_inserter(body),
                       "  transition t{0} {{ wait {{ {1}, ready }} signal {{ s{2}*2, ready }} }}\n", j, wait_stage(),
                       j + 1);
        uses_ready = true;
        w = 2;
        left -= 1;
        break;
      case 3:
        fmt::format_to(std::back_inserter(body),
                       "  transition t{0} {{\n"
                       "    wait   {{ {1} }}\n"
                       "    action {{ TACTIC(REPORT, \"stage {0}\"),"
                       " TACTIC(EXEC, goto_depth(12.5, 3), s{2}) }}\n"
                       "  }}\n",
                       j, wait_stage(), j + 1);
        w = 1;
        left -= 1;
        break;
      default:
        fmt::format_to(std::back_inserter(body),
                       "  transition t{0} priority 2 {{\n"
                       "    wait   {{ {1} }}\n"
                       "    action {{ TACTIC(ASK, battery_ok, s{2}, abort) }}\n"
                       "  }}\n",
                       j, wait_stage(), j + 1);
        uses_abort = true;
        w = 1;
        left -= 1;
        break;
    }
  }
  places.push_back(fmt::format("s{}", j));
  if (uses_abort) {
    fmt::format_to(std::back_inserter(body), "  transition finish {{ wait {{ {} }} signal {{ complete }} }}\n",
                   wait_stage());
  } else {
    // Nothing else marks abort: let the last stage choose, so the exit is live.
    fmt::format_to(std::back_inserter(body),
                   "  transition finish {{ wait {{ {} }}"
                   " action {{ TACTIC(ASK, survey_ok, complete, abort) }} }}\n",
                   wait_stage());
  }

  fmt::format_to(std::back_inserter(out), "net phase{} {{\n", index);
  for (std::size_t i = 0; i < places.size(); i += 8) {
    out += "  place ";
    for (std::size_t p = i; p < std::min(places.size(), i + 8); ++p) {
      if (p != i) out += ", ";
      out += places[p];
      if (p == 0) out += " = 1";
    }
    out += ";\n";
  }
  if (uses_ready) out += "  place ready = 1;\n";
  out += "  exit complete, abort;\n";
  out += body;
  out += "}\n\n";
}

// A mission running `phases` phase nets in sequence, each abort reported and
// sent to the mission's `failed` exit: 2 * phases + 1 transitions.
void append_mission(std::string& out, std::size_t phases) {
  out += "mission survey {\n  data \"x.toml\";\n  place begin = 1;\n";
  for (std::size_t i = 0; i < phases; ++i) {
    fmt::format_to(std::back_inserter(out), "  place ok{0}, fail{0};\n", i);
  }
  out += "  exit done, failed;\n";
  for (std::size_t i = 0; i < phases; ++i) {
    std::string from = i == 0 ? "begin" : fmt::format("ok{}", i - 1);
    fmt::format_to(std::back_inserter(out),
                   "  transition go{0} {{\n"
                   "    wait   {{ {1} }}\n"
                   "    action {{ PHASE(phase{0}, ok{0}, fail{0}) }}\n"
                   "  }}\n"
                   "  transition bail{0} {{\n"
                   "    wait   {{ fail{0} }}\n"
                   "    action {{ TACTIC(REPORT, \"phase {0} aborted\") }}\n"
                   "    signal {{ failed }}\n"
                   "  }}\n",
                   i, from);
  }
  fmt::format_to(std::back_inserter(out),
                 "  transition finish {{ wait {{ ok{} }}"
                 " action {{ TACTIC(OOD, shutdown_network, done) }} }}\n"
                 "}}\n",
                 phases - 1);
}

Generated generate_mission(std::size_t transitions) {
  const std::size_t phases = std::max<std::size_t>(1, transitions / kTransitionsPerPhase);
  const std::size_t in_mission = 2 * phases + 1;
  const std::size_t in_phases = transitions - in_mission;
  Generated g;
  g.text.reserve(transitions * 120);
  g.text += "// Generated by bench/coral_bench.cpp\n\n";
  for (std::size_t i = 0; i < phases; ++i) {
    append_phase(g.text, i, in_phases / phases + (i < in_phases % phases ? 1 : 0));
  }
  append_mission(g.text, phases);
  g.transitions = transitions;
  return g;
}

// A mission with a chain of transitions t_i: s_i -> s_(i+1), declared from
// the last link to the first, then one transition into the exit.
Generated generate_reversed_chain(std::size_t transitions) {
  Generated g;
  const std::size_t links = transitions - 1;
  g.text += "mission chain {\n  data \"x.toml\";\n";
  for (std::size_t i = 0; i <= links; ++i) {
    g.text += i % 8 == 0 ? (i == 0 ? "  place s0 = 1" : ";\n  place ") : ", ";
    if (i != 0) fmt::format_to(std::back_inserter(g.text), "s{}", i);
  }
  g.text += ";\n  exit done;\n";
  for (std::size_t i = links; i-- > 0;) {
    fmt::format_to(std::back_inserter(g.text),
                   "  transition t{0} {{ wait {{ s{0} }}"
                   " action {{ TACTIC(EXEC, next_setpt_data, s{1}) }} }}\n",
                   i, i + 1);
  }
  fmt::format_to(std::back_inserter(g.text),
                 "  transition finish {{ wait {{ s{} }}"
                 " action {{ TACTIC(OOD, shutdown_network, done) }} }}\n}}\n",
                 links);
  g.transitions = transitions;
  return g;
}

enum class Shape { kMission, kReversedChain };

struct Fixture {
  Generated source;
  MemoryFileProvider files;
  std::string problem;  // non-empty: the text does not compile as intended
  std::size_t warnings = 0;
};

const Fixture& fixture(Shape shape, std::size_t transitions) {
  static std::map<std::pair<Shape, std::size_t>, Fixture> cache;
  auto [it, fresh] = cache.try_emplace({shape, transitions});
  Fixture& f = it->second;
  if (!fresh) return f;
  f.source = shape == Shape::kMission ? generate_mission(transitions) : generate_reversed_chain(transitions);
  f.files.add(kFileName, f.source.text);

  core::SourceManager sources;
  core::DiagnosticSink sink(1000);
  auto program = compile_file(kFileName, f.files, sources, sink);
  f.warnings = sink.warning_count();
  for (const auto& d : sink.diagnostics()) {
    if (d.severity == core::Severity::Error) {
      auto lc = sources.line_col(d.span.file, d.span.offset);
      f.problem = fmt::format("{}:{}:{}: {} [{}]", kFileName, lc.line, lc.col, d.message, core::kind_name(d.kind));
      return f;
    }
  }
  if (!program) {
    f.problem = "compile_file returned no program and reported no error";
    return f;
  }
  std::size_t compiled = 0;
  for (const auto& net : program->nets) compiled += net.net.transition_count();
  if (compiled != transitions || !program->mission) {
    f.problem = fmt::format("compiled {} transitions, expected {}", compiled, transitions);
  }
  return f;
}

void report(benchmark::State& st, const Fixture& f) {
  const auto iterations = static_cast<double>(st.iterations());
  st.SetBytesProcessed(st.iterations() * static_cast<std::int64_t>(f.source.text.size()));
  st.counters["transitions_per_second"] =
      benchmark::Counter(iterations * static_cast<double>(f.source.transitions), benchmark::Counter::kIsRate);
  st.counters["source_KiB"] = static_cast<double>(f.source.text.size()) / 1024.0;
  st.counters["warnings"] = static_cast<double>(f.warnings);
}

void bm_load(benchmark::State& st) {
  const Fixture& f = fixture(Shape::kMission, static_cast<std::size_t>(st.range(0)));
  if (!f.problem.empty()) {
    st.SkipWithError(f.problem.c_str());
    return;
  }
  for (auto _ : st) {
    core::SourceManager sources;
    core::DiagnosticSink sink(1000);
    Load l = load(kFileName, f.files, sources, sink);
    benchmark::DoNotOptimize(l.files.data());
    if (sink.has_errors()) {
      st.SkipWithError("load reported an error");
      break;
    }
  }
  report(st, f);
}

void bm_compile_file(benchmark::State& st, Shape shape) {
  const Fixture& f = fixture(shape, static_cast<std::size_t>(st.range(0)));
  if (!f.problem.empty()) {
    st.SkipWithError(f.problem.c_str());
    return;
  }
  for (auto _ : st) {
    core::SourceManager sources;
    core::DiagnosticSink sink(1000);
    auto program = compile_file(kFileName, f.files, sources, sink);
    if (!program) {
      st.SkipWithError("compile_file failed");
      break;
    }
    benchmark::DoNotOptimize(program->nets.data());
  }
  report(st, f);
}

BENCHMARK(bm_load)
    ->Name("coral/load")
    ->ArgName("transitions")
    ->Arg(1'000)
    ->Arg(10'000)
    ->Arg(100'000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bm_compile_file, mission, Shape::kMission)
    ->Name("coral/compile_file")
    ->ArgName("transitions")
    ->Arg(1'000)
    ->Arg(10'000)
    ->Arg(100'000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bm_compile_file, reversed_chain, Shape::kReversedChain)
    ->Name("coral/compile_file_reversed_chain")
    ->ArgName("transitions")
    ->Arg(1'000)
    ->Arg(2'000)
    ->Arg(4'000)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace strata::coral
