#pragma once
// `strata campaign SPEC --slurm --out DIR`: a campaign as a Slurm job array
// and a merge job that depends on it (docs/campaigns.md, "Slurm"). DIR gets
//
//   campaign.sbatch  the array: task I runs `--shard I/N` into DIR/shard-I
//   merge.sbatch     `--merge DIR/shard-0 ... DIR/shard-(N-1) --out DIR/merged`
//   submit.sh        sbatch of the array, then of the merge with
//                    --dependency=afterok on the array (what --submit runs)
//
// and, once they ran, Slurm's output of each task (slurm-A_I.out) and of the
// merge (slurm-merge-J.out). Every path in the scripts is absolute and
// single-quoted in one assignment, then used only inside double quotes: a
// path with spaces, quotes, `$(...)` or newlines is data, never shell code,
// and no path is written on an #SBATCH line.
//
// A task whose shard ran but had cases failing their expectations (strata's
// exit 1) succeeds, so afterok means "every shard ran to its end" and the
// merge reports the failures (its own exit 1); any other exit of a task (a
// bad spec, a folder it cannot write, a signal) fails the task, and the
// merge never runs.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace strata::campaign {

// The most array tasks --shards asks for (a cluster's MaxArraySize, 1001 by
// default, may allow fewer).
inline constexpr std::uint64_t kMaxSlurmShards = 100'000;

struct SlurmOptions {
  std::string strata;  // the strata executable the jobs run (absolute)
  std::string spec;    // the spec (absolute)
  std::string dir;     // the scripts, the shards, Slurm's output and merged/ (absolute)
  std::uint64_t shards = 16;
  int cpus_per_task = 1;  // each task's -j
  std::string partition;  // empty: the cluster's default
  std::string time;       // each job's time limit; empty: the partition's default
  std::string job_name = "strata-campaign";
  std::vector<std::string> sbatch_args;  // more #SBATCH options, e.g. "--account=ocean"
  std::vector<std::string> task_args;    // more arguments of each task (--keep-logs failed, ...)
  std::vector<std::string> spec_args;    // more arguments of the tasks and the merge (--max-cases N)
};

struct SlurmScripts {
  std::string array;   // campaign.sbatch
  std::string merge;   // merge.sbatch
  std::string submit;  // submit.sh
};

// The three scripts. InvalidInput, naming the option, when a value cannot be
// written safely or is not one Slurm takes: a relative path, shards or
// cpus_per_task out of range, a partition or job name outside
// [A-Za-z0-9_.,-], a time not in Slurm's forms (minutes, M:S, H:M:S, D-H,
// D-H:M, D-H:M:S, UNLIMITED), an sbatch option not starting with '-' or
// holding a control character.
core::Result<SlurmScripts> slurm_scripts(const SlurmOptions& options);

// Writes the scripts into dir (created if missing; executable). dir must
// not be a symbolic link, and an existing dir must be empty or hold an
// earlier --slurm campaign (a campaign.sbatch): its scripts are replaced,
// nothing else is touched. Io error otherwise.
core::Result<void> write_slurm_scripts(const std::string& dir, const SlurmScripts& scripts);

// s as one word of POSIX sh: in single quotes, each ' written as '\''.
std::string shell_quote(std::string_view s);

// The job id in `sbatch --parsable`'s output ("123" or "123;cluster", with
// a trailing newline); InvalidInput when it holds none.
core::Result<std::string> parse_sbatch_job_id(std::string_view output);

struct SlurmJobs {
  std::string array_id, merge_id;
};

// Submits dir's campaign.sbatch, then merge.sbatch with
// --dependency=afterok:<array id>, both with --chdir=dir, running sbatch
// (an absolute path; see find_on_path) and waiting at most `bound_s` seconds
// for each. Errors name the command and carry what sbatch wrote on stderr:
// Io when it cannot be started, did not end in time, failed, or printed no
// job id.
core::Result<SlurmJobs> submit_slurm(const std::string& dir, const std::string& sbatch, double bound_s = 120.0);

// The first executable file called name in $PATH's folders; "" when none.
std::string find_on_path(std::string_view name);

}  // namespace strata::campaign
