#pragma once
// `strata campaign SPEC --merge DIR... --out DIR`: the folders of several
// runs of one spec's cases (shards: --shard I/N, --cases A-B, Slurm array
// tasks) joined into one folder with the same results.jsonl (sorted by
// index), report.json and report.html as a single local run, and the
// failing cases' logs and scenarios copied over.
#include <string>
#include <vector>

#include "campaign/spec.h"
#include "core/result.h"

namespace strata::campaign {

struct MergeOutcome {
  std::uint64_t planned = 0, done = 0, failed = 0;
  std::uint64_t duplicates = 0;  // a case in more than one folder: the first kept
};

// Errors: Io (a folder or file cannot be read or written), InvalidInput (a
// line that is not a result, or a case index the spec does not have).
core::Result<MergeOutcome> merge_campaigns(const Spec& spec, const std::vector<std::string>& dirs,
                                           const std::string& out_dir, const std::string& command);

// The indices i of [0, count) with i % n == shard: every n-th case from the
// shard-th, for --shard I/N ("I/N", 0 <= I < N).
core::Result<std::vector<std::uint64_t>> shard_indices(const std::string& text, std::uint64_t count);

}  // namespace strata::campaign
