#pragma once
// The local pool: N worker processes, forked once each, every one running
// many cases in-process (campaign::run_case), handed lists of case indices
// over a pipe and answering one line per case over another:
//   parent -> worker   "I J K\n"         run these cases, in order
//   worker -> parent   "S I\n"           case I started
//                      "R {json}\n"      case I's line of results.jsonl
// A worker exits when its command pipe closes. One that dies (a crash, a
// kill) costs the case it had started: that case is reported as crashed
// with the reason, the rest of its list goes back in the queue, and a new
// worker takes its place. A case running past the wall-time limit gets its
// worker killed the same way. Nothing waits without a bound.
//
// Threads: none; call from a process with no other threads (fork). The
// parent must not have started SWI-Prolog: each worker starts its own.
#include <csignal>
#include <cstdint>
#include <functional>
#include <vector>

#include <nlohmann/json.hpp>

#include "campaign/case_run.h"
#include "campaign/spec.h"

namespace strata::campaign {

struct PoolOptions {
  int workers = 1;
  double case_wall_limit_s = 120.0;  // one case's wall time before its worker is killed
  // Told each case's line as it arrives (results are written as they come).
  std::function<void(const nlohmann::ordered_json&)> on_result;
  // Told about four times a second, and after each result.
  std::function<void()> on_tick;
  // The count of stop requests (signals) so far; the pool reads it. One:
  // no new cases, every worker finishes the case it is running and exits
  // (killed after a few seconds). Two: the workers are killed at once.
  const volatile std::sig_atomic_t* stop_requests = nullptr;
};

struct PoolOutcome {
  std::uint64_t done = 0;  // cases with a line (crashed ones included)
  bool stopped = false;    // a stop request ended it before every case ran
};

// indices: distinct case indices of the spec.
PoolOutcome run_pool(const Spec& spec, const std::vector<std::uint64_t>& indices, const CaseRunConfig& config,
                     const PoolOptions& options);

// The same cases run one after another in this process (no fork): --case,
// and -j 1 in tests. Stops between cases on a stop request.
PoolOutcome run_inline(const Spec& spec, const std::vector<std::uint64_t>& indices, const CaseRunConfig& config,
                       const PoolOptions& options);

}  // namespace strata::campaign
