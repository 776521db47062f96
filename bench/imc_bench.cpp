// The IMC codec's cost (src/imc):
//
//   imc/decode/EstimatedState   decode() of one EstimatedState datagram;
//                               items_per_second is messages/s (target
//                               >= 1 M/s on one core, release build)
//   imc/encode/Reference        encode() of a Reference with inline
//                               DesiredSpeed and DesiredZ
//   imc/filter/dune_mix         one second of what a DUNE LAUV simulator
//   imc/decode_all/dune_mix     sends a registered peer while manoeuvring
//                               (the facts measured for issue 35: ~815
//                               packets/s): filter = peek_header and an id
//                               filter, decoding only what a controller
//                               wants (EstimatedState, VehicleState,
//                               PlanControlState, GpsFix, Heartbeat,
//                               FollowRefState, PlanControl, LogBookEntry,
//                               Announce); decode_all = decode() of every
//                               packet. ns_per_packet over the mix, and
//                               core_pct_at_800 = the share of one core that
//                               800 such packets a second take.
#include <benchmark/benchmark.h>

#include <bitset>
#include <ctime>
#include <cstdint>
#include <utility>
#include <variant>
#include <vector>

#include "imc/codec.h"
#include "imc/codec_test_support.h"

namespace strata::imc {
namespace {

using Bytes = std::vector<std::uint8_t>;

Header bench_header() {
  Header h;
  h.timestamp = 1.7e9;
  h.src = 0x00D1;
  h.src_ent = 12;
  h.dst = 0x4001;
  h.dst_ent = 0xFF;
  return h;
}

Bytes encoded(Message m) { return encode(Packet{bench_header(), std::move(m)}).value(); }

// A datagram of a message the table does not have: `payload_bytes` zeros
// under `mgid`, with a valid header and CRC (what DUNE's high-rate
// messages look like to the filter).
Bytes foreign(std::uint16_t mgid, std::size_t payload_bytes) {
  Bytes out = encoded(Heartbeat{});  // the bench's header, then patched
  out.resize(kHeaderBytes);
  out[2] = static_cast<std::uint8_t>(mgid & 0xFF);
  out[3] = static_cast<std::uint8_t>(mgid >> 8);
  out[4] = static_cast<std::uint8_t>(payload_bytes & 0xFF);
  out[5] = static_cast<std::uint8_t>(payload_bytes >> 8);
  out.resize(kHeaderBytes + payload_bytes, 0);
  return testing::with_crc(std::move(out));
}

EstimatedState estimated_state() { return testing::sample_estimated_state(); }
Reference reference() { return testing::sample_reference(); }

// One second of a manoeuvring LAUV simulator, interleaved as the rates
// interleave (the measured rates; payload sizes per IMC 5.4).
std::vector<Bytes> dune_mix() {
  struct Stream {
    Bytes bytes;
    int per_second;
  };
  VehicleState vs;
  vs.op_mode = VehicleState::kOpModeManeuver;
  vs.maneuver_type = FollowReference::kId;
  PlanControlState pcs;
  pcs.state = PlanControlState::kStateExecuting;
  pcs.plan_id = "strata-follow";
  pcs.man_id = "follow";
  GpsFix fix;
  fix.validity = 0x1FF;
  fix.satellites = 9;
  const std::vector<Stream> streams = {
      {foreign(281, 5), 400},                                              // ServoPosition
      {foreign(257, 32), 100},                                             // Acceleration
      {foreign(256, 32), 100},                                             // AngularVelocity
      {foreign(254, 40), 100},                                             // EulerAngles
      {encoded(EntityState{EntityState::kStateNormal, 0, "active"}), 53},  // EntityState (known, unwanted)
      {foreign(301, 5), 20},                                               // SetThrusterActuation
      {foreign(408, 8), 20},                                               // DesiredHeadingRate
      {foreign(410, 81), 1},                                               // PathControlState
      {encoded(estimated_state()), 2},
      {encoded(vs), 2},
      {encoded(pcs), 3},
      {encoded(fix), 1},
      {encoded(Heartbeat{}), 1},
      {encoded(FollowRefState{0x4001, 5, reference(), FollowRefState::kStateGoto, FollowRefState::kProxFar}), 1},
  };
  std::vector<Bytes> out;
  // Slot k of 1000 gets stream s when s's k-th share falls there.
  for (int slot = 0; slot < 1000; ++slot) {
    for (const Stream& s : streams) {
      if ((slot + 1) * s.per_second / 1000 != slot * s.per_second / 1000) out.push_back(s.bytes);
    }
  }
  return out;
}

std::bitset<65536> wanted_ids() {
  std::bitset<65536> wanted;
  for (std::uint16_t id : {EstimatedState::kId, VehicleState::kId, PlanControlState::kId, GpsFix::kId, Heartbeat::kId,
                           FollowRefState::kId, PlanControl::kId, LogBookEntry::kId, Announce::kId}) {
    wanted.set(id);
  }
  return wanted;
}

void BM_DecodeEstimatedState(benchmark::State& state) {
  const Bytes bytes = encoded(estimated_state());
  for (auto _ : state) {
    auto result = decode(bytes);
    benchmark::DoNotOptimize(result);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes.size()));
}
BENCHMARK(BM_DecodeEstimatedState)->Name("imc/decode/EstimatedState");

void BM_EncodeReference(benchmark::State& state) {
  const Packet packet{bench_header(), reference()};
  for (auto _ : state) {
    auto bytes = encode(packet);
    benchmark::DoNotOptimize(bytes);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_EncodeReference)->Name("imc/encode/Reference");

// This thread's CPU time, ns (the figures are about a core's share, and
// the machine may be busy with other work).
double thread_cpu_ns() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e9 + static_cast<double>(t.tv_nsec);
}

// Runs `per_packet` over the mix each iteration; reports the mix's size,
// the CPU time per packet (ns_per_packet) and the share of one core, in
// percent, that 800 such packets a second take (core_pct_at_800; Google
// Benchmark prints 0.0003 as 300u).
template <typename PerPacket>
void run_mix(benchmark::State& state, PerPacket per_packet) {
  const std::vector<Bytes> mix = dune_mix();
  std::uint64_t packets = 0;
  const double start = thread_cpu_ns();
  for (auto _ : state) {
    for (const Bytes& datagram : mix) per_packet(datagram);
    packets += mix.size();
  }
  const double ns_per_packet = (thread_cpu_ns() - start) / static_cast<double>(packets);
  state.counters["packets_per_mix"] = static_cast<double>(mix.size());
  state.counters["ns_per_packet"] = ns_per_packet;
  state.counters["core_pct_at_800"] = ns_per_packet * 800.0 / 1e9 * 100.0;
  state.SetItemsProcessed(static_cast<std::int64_t>(packets));
}

void BM_FilterDuneMix(benchmark::State& state) {
  const std::bitset<65536> wanted = wanted_ids();
  DropCounts drops;
  std::uint64_t kept = 0;
  run_mix(state, [&](const Bytes& datagram) {
    auto header = peek_header(datagram);
    if (!header || !wanted.test(header->mgid)) {
      drops.add(Drop::Filtered);
      return;
    }
    auto result = decode(datagram);
    if (const Drop* d = std::get_if<Drop>(&result)) {
      drops.add(*d);
    } else {
      ++kept;
      benchmark::DoNotOptimize(result);
    }
  });
  state.counters["kept_per_mix"] = static_cast<double>(kept) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_FilterDuneMix)->Name("imc/filter/dune_mix");

void BM_DecodeAllDuneMix(benchmark::State& state) {
  DropCounts drops;
  run_mix(state, [&](const Bytes& datagram) {
    auto result = decode(datagram);
    if (const Drop* d = std::get_if<Drop>(&result)) drops.add(*d);
    benchmark::DoNotOptimize(result);
  });
}
BENCHMARK(BM_DecodeAllDuneMix)->Name("imc/decode_all/dune_mix");

}  // namespace
}  // namespace strata::imc
