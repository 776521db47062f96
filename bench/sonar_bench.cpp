// The Sonar Manager's processing stage (issue 8): pings processed per second
// at 200 bins, image and detection, with and without writing the frames, to
// compare with the 200 pings/s it must keep up with at 10x real time (the
// vehicle pings at 20/s). Also the parts alone, and the whole manager over
// loopback. Pings come from the test-only synthesiser (sonar/test_support.h).
#include <benchmark/benchmark.h>

#include <filesystem>

#include "sonar/manager.h"
#include "sonar/output.h"
#include "sonar/processor.h"
#include "sonar/test_support.h"

namespace {

using namespace strata;
using sonar::testing::PingSynth;
using sonar::testing::SynthConfig;

// Ten sweeps (about 665 pings) of the tank with a target in it.
const std::vector<protocol::SonarPing>& pings() {
  static const auto all = [] {
    SynthConfig c;
    c.target = sonar::testing::SynthTarget{8.5, 6.0, 0.15};
    PingSynth synth(c);
    return synth.sweeps(10);
  }();
  return all;
}

void BM_ProcessPings(benchmark::State& state) {
  sonar::ProcessorOptions o;
  o.image.size_px = static_cast<int>(state.range(0));
  std::uint64_t frames = 0;
  for (auto _ : state) {
    sonar::Processor processor(o);
    for (const auto& ping : pings()) {
      if (auto f = processor.add_ping(ping)) benchmark::DoNotOptimize(f->detection.walls.size()), ++frames;
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(pings().size()));
  state.counters["pings/s"] =
      benchmark::Counter(static_cast<double>(state.iterations() * pings().size()), benchmark::Counter::kIsRate);
  state.counters["frames"] = static_cast<double>(frames) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_ProcessPings)->Arg(400)->Arg(800)->Unit(benchmark::kMillisecond);

// As the manager does it: each frame also encoded as PNG and written twice
// (scan and latest.png), its JSON line left out.
void BM_ProcessPingsAndWriteFrames(benchmark::State& state) {
  const auto dir = sonar::testing::fresh_dir("bench");
  auto out = sonar::OutputDir::open(dir);
  if (!out) {
    state.SkipWithError(out.error().message.c_str());
    return;
  }
  for (auto _ : state) {
    sonar::Processor processor;
    for (const auto& ping : pings()) {
      if (auto f = processor.add_ping(ping)) benchmark::DoNotOptimize(out.value().write_frame(f->frame, f->image).ok());
    }
  }
  state.counters["pings/s"] =
      benchmark::Counter(static_cast<double>(state.iterations() * pings().size()), benchmark::Counter::kIsRate);
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_ProcessPingsAndWriteFrames)->Unit(benchmark::kMillisecond);

void BM_PaintOnePing(benchmark::State& state) {
  sonar::ScanImage scan;
  std::size_t i = 0;
  for (auto _ : state) scan.paint(pings()[i++ % pings().size()], 1.8);
  state.counters["pings/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PaintOnePing);

void BM_FindEcho(benchmark::State& state) {
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(sonar::find_echo(pings()[i++ % pings().size()]));
}
BENCHMARK(BM_FindEcho);

// Walls and target over a two-sweep window (what each frame costs).
void BM_DetectTwoSweeps(benchmark::State& state) {
  std::vector<sonar::EchoPoint> points;
  for (std::size_t i = 0; i < 133; ++i) {
    if (auto e = sonar::find_echo(pings()[i])) points.push_back(*e);
  }
  for (auto _ : state) benchmark::DoNotOptimize(sonar::detect(points, {7.0, 4.5, 45.0}));
  state.counters["points"] = static_cast<double>(points.size());
}
BENCHMARK(BM_DetectTwoSweeps)->Unit(benchmark::kMicrosecond);

// The whole manager: a test server sends 10 000 pings as fast as loopback
// takes them, the manager captures, processes and writes every frame.
void BM_ManagerOverLoopback(benchmark::State& state) {
  std::string stream = protocol::encode_sonar(protocol::SonarStatus{0.0, true, 0, 0});
  {
    PingSynth synth(SynthConfig{});
    for (int i = 0; i < 10000; ++i) stream += protocol::encode_sonar(synth.next());
    stream += protocol::encode_sonar(protocol::SonarEnd{500.0, 10000, 0, "bench"});
  }
  const auto dir = sonar::testing::fresh_dir("bench_manager");
  std::uint64_t processed = 0, dropped = 0;
  for (auto _ : state) {
    sonar::testing::TestServer server([&](sonar::testing::TestConnection& c) { c.send(stream); });
    sonar::ManagerOptions o;
    o.capture.port = server.port();
    o.out_dir = dir;
    o.log = [](const std::string&) {};
    const auto s = sonar::run_sonar_manager(o);
    processed += s.processed;
    dropped += s.capture.queue_drops;
  }
  state.counters["pings/s"] = benchmark::Counter(static_cast<double>(processed), benchmark::Counter::kIsRate);
  state.counters["queue_drops"] = static_cast<double>(dropped);
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_ManagerOverLoopback)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
