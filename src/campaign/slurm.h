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

// Why a submission failed, for the caller to say what to do next.
enum class SubmitProblem {
  Other,         // sbatch could not be run, failed otherwise, or printed no job id
  NoCluster,     // no Slurm configuration: SLURM_CONF names no file, or sbatch found
                 // no slurm.conf and no DNS SRV record naming a controller
  NoController,  // the configuration's controller (slurmctld) did not answer
};

struct SubmitError : core::Error {
  SubmitProblem problem = SubmitProblem::Other;
};

// The problem sbatch's stderr reports, from Slurm's own messages (22.05:
// "fetch_config: DNS SRV lookup failed", "Could not establish a
// configuration source"; "Unable to contact slurm controller"); Other for
// any other text.
SubmitProblem sbatch_problem(std::string_view sbatch_stderr);

// Submits dir's campaign.sbatch, then merge.sbatch with
// --dependency=afterok:<array id>, both with --chdir=dir, running sbatch
// (an absolute path; see find_on_path) and waiting at most `bound_s` seconds
// for each. Errors (Io) name the command and carry what sbatch wrote on
// stderr, with the problem: NoCluster before any sbatch runs when
// $SLURM_CONF is set and names no regular file (sbatch would retry it for a
// minute), else what sbatch_problem reads in its stderr when it failed.
core::Result<SlurmJobs, SubmitError> submit_slurm(const std::string& dir, const std::string& sbatch,
                                                  double bound_s = 120.0);

// The first executable file called name in $PATH's folders; "" when none.
std::string find_on_path(std::string_view name);

}  // namespace strata::campaign
