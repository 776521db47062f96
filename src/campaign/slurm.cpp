#include "campaign/slurm.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <regex>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "campaign/output.h"
#include "core/file.h"

extern char** environ;

namespace strata::campaign {
namespace {

namespace fs = std::filesystem;

core::Error invalid(std::string message) { return core::make_error(core::ErrorCode::InvalidInput, std::move(message)); }

bool has_control_char(std::string_view s) {
  for (unsigned char c : s) {
    if (c < 0x20 || c == 0x7f) return true;
  }
  return false;
}

core::Result<void> check_options(const SlurmOptions& o) {
  for (const auto& [name, path] : {std::pair{"the strata executable", &o.strata}, std::pair{"the spec", &o.spec},
                                   std::pair{"the folder", &o.dir}}) {
    if (path->empty() || !fs::path(*path).is_absolute()) {
      return invalid(fmt::format("{} must be an absolute path, not '{}'", name, *path));
    }
  }
  if (o.shards < 1 || o.shards > kMaxSlurmShards) {
    return invalid(fmt::format("--shards {}: must be 1 to {}", o.shards, kMaxSlurmShards));
  }
  if (o.cpus_per_task < 1 || o.cpus_per_task > 1024) {
    return invalid(fmt::format("-j {}: CPUs per task must be 1 to 1024", o.cpus_per_task));
  }
  static const std::regex name_chars(R"([A-Za-z0-9_.,-]+)");
  if (!o.partition.empty() && !std::regex_match(o.partition, name_chars)) {
    return invalid(fmt::format("--partition '{}': a partition name is letters, digits and _ . , - only", o.partition));
  }
  if (!std::regex_match(o.job_name, name_chars)) {
    return invalid(fmt::format("job name '{}': letters, digits and _ . , - only", o.job_name));
  }
  static const std::regex time_forms(R"(UNLIMITED|INFINITE|\d+(:\d+){0,2}|\d+-\d+(:\d+){0,2})");
  if (!o.time.empty() && !std::regex_match(o.time, time_forms)) {
    return invalid(
        fmt::format("--time '{}': not a Slurm time (minutes, M:S, H:M:S, D-H, D-H:M, D-H:M:S or UNLIMITED)", o.time));
  }
  for (const std::string& a : o.sbatch_args) {
    if (a.size() < 2 || a[0] != '-' || has_control_char(a)) {
      return invalid(fmt::format("--sbatch '{}': an sbatch option such as --account=NAME, on one line", a));
    }
  }
  return {};
}

// The lines every script starts with: the directives both jobs share.
std::string shared_directives(const SlurmOptions& o) {
  std::string s;
  if (!o.partition.empty()) s += fmt::format("#SBATCH --partition={}\n", o.partition);
  if (!o.time.empty()) s += fmt::format("#SBATCH --time={}\n", o.time);
  for (const std::string& a : o.sbatch_args) s += fmt::format("#SBATCH {}\n", a);
  return s;
}

// The paths, each assigned once in single quotes.
std::string assignments(const SlurmOptions& o) {
  return fmt::format("strata={}\nspec={}\ndir={}\nshards={}\n", shell_quote(o.strata), shell_quote(o.spec),
                     shell_quote(o.dir), o.shards);
}

std::string quoted_words(const std::vector<std::string>& words) {
  std::string s;
  for (const std::string& w : words) s += " " + shell_quote(w);
  return s;
}

struct Ran {
  int status = -1;  // waitpid's status
  std::string out, err;
};

// Runs argv[0] (an absolute path) with stdin on /dev/null, stdout and
// stderr read through pipes; at most bound_s seconds, then killed by pid.
core::Result<Ran> run_captured(const std::vector<std::string>& args, double bound_s) {
  int out_pipe[2], err_pipe[2];
  if (::pipe2(out_pipe, O_CLOEXEC) != 0) return core::errno_error("pipe");
  if (::pipe2(err_pipe, O_CLOEXEC) != 0) {
    ::close(out_pipe[0]);
    ::close(out_pipe[1]);
    return core::errno_error("pipe");
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out_pipe[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, err_pipe[1], STDERR_FILENO);
  std::vector<std::string> copy = args;
  std::vector<char*> argv;
  argv.reserve(copy.size() + 1);
  for (std::string& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(out_pipe[1]);
  ::close(err_pipe[1]);
  Ran ran;
  if (spawned != 0) {
    ::close(out_pipe[0]);
    ::close(err_pipe[0]);
    return core::make_error(core::ErrorCode::Io, fmt::format("cannot start {}: {}", args[0], std::strerror(spawned)));
  }
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(static_cast<long long>(bound_s * 1000));
  pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
  std::string* into[2] = {&ran.out, &ran.err};
  bool timed_out = false;
  while (fds[0].fd >= 0 || fds[1].fd >= 0) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      timed_out = true;
      break;
    }
    const int n = ::poll(fds, 2, static_cast<int>(left.count()));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) break;
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || fds[i].revents == 0) continue;
      char buf[4096];
      const ssize_t got = ::read(fds[i].fd, buf, sizeof buf);
      if (got > 0 && into[i]->size() < (std::size_t{1} << 20)) {
        into[i]->append(buf, static_cast<std::size_t>(got));
      } else if (got == 0 || (got < 0 && errno != EINTR && errno != EAGAIN)) {
        ::close(fds[i].fd);
        fds[i].fd = -1;
      }
    }
  }
  for (auto& f : fds) {
    if (f.fd >= 0) ::close(f.fd);
  }
  if (timed_out) ::kill(pid, SIGKILL);
  while (::waitpid(pid, &ran.status, 0) < 0 && errno == EINTR) {}
  if (timed_out) {
    return core::make_error(core::ErrorCode::Io,
                            fmt::format("{} did not end within {:g} s and was stopped", args[0], bound_s));
  }
  return ran;
}

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  return s;
}

SubmitError submit_error(std::string message, SubmitProblem problem = SubmitProblem::Other) {
  SubmitError e;
  e.code = core::ErrorCode::Io;
  e.message = std::move(message);
  e.problem = problem;
  return e;
}

core::Result<std::string, SubmitError> sbatch_once(const std::vector<std::string>& args, double bound_s) {
  const std::string shown = fmt::format("{}", fmt::join(args, " "));
  auto ran = run_captured(args, bound_s);
  if (!ran) return submit_error(ran.error().message);
  const Ran& r = ran.value();
  if (!WIFEXITED(r.status) || WEXITSTATUS(r.status) != 0) {
    const std::string why = WIFEXITED(r.status) ? fmt::format("exit {}", WEXITSTATUS(r.status))
                                                : fmt::format("signal {}", WTERMSIG(r.status));
    return submit_error(fmt::format("{} failed ({}){}{}", shown, why, r.err.empty() ? "" : ": ", trimmed(r.err)),
                        sbatch_problem(r.err));
  }
  auto id = parse_sbatch_job_id(r.out);
  if (!id) {
    return submit_error(
        fmt::format("{}: {}{}{}", shown, id.error().message, r.err.empty() ? "" : "; stderr: ", trimmed(r.err)));
  }
  return id.value();
}

}  // namespace

std::string shell_quote(std::string_view s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') {
      q += "'\\''";
    } else {
      q += c;
    }
  }
  q += "'";
  return q;
}

core::Result<SlurmScripts> slurm_scripts(const SlurmOptions& o) {
  if (auto ok = check_options(o); !ok) return ok.error();
  SlurmScripts s;
  s.array = fmt::format(
      "#!/bin/sh\n"
      "# A campaign as a Slurm job array, written by `strata campaign --slurm`\n"
      "# (docs/campaigns.md). Task I runs every {0}-th case from the I-th into\n"
      "# shard-I/; merge.sbatch joins the shards once every task succeeded.\n"
      "# Submit both with submit.sh.\n"
      "#SBATCH --job-name={1}\n"
      "#SBATCH --array=0-{2}\n"
      "#SBATCH --cpus-per-task={3}\n"
      "#SBATCH --output=slurm-%A_%a.out\n"
      "{4}"
      "set -u\n"
      "{5}"
      "task=\"${{SLURM_ARRAY_TASK_ID:?not run as a Slurm array task}}\"\n"
      "\"$strata\" campaign \"$spec\" --shard \"$task/$shards\" --out \"$dir/shard-$task\" \\\n"
      "  -j \"${{SLURM_CPUS_PER_TASK:-{3}}}\"{6}\n"
      "status=$?\n"
      "# 1: the shard ran and some of its cases failed their expectations; the\n"
      "# merge reports them, so the task succeeded. Any other code is an error\n"
      "# (a bad spec, a folder it cannot write, a signal), and the merge waits\n"
      "# for every task to succeed (afterok).\n"
      "if [ \"$status\" -eq 1 ]; then exit 0; fi\n"
      "exit \"$status\"\n",
      o.shards, o.job_name, o.shards - 1, o.cpus_per_task, shared_directives(o), assignments(o),
      quoted_words(o.task_args) + quoted_words(o.spec_args));
  s.merge = fmt::format(
      "#!/bin/sh\n"
      "# The merge of the campaign's {0} shards into merged/, written by\n"
      "# `strata campaign --slurm`: submitted with --dependency=afterok on the\n"
      "# array of campaign.sbatch. Exit 0 when every case is there and passed.\n"
      "#SBATCH --job-name={1}-merge\n"
      "#SBATCH --cpus-per-task=1\n"
      "#SBATCH --output=slurm-merge-%j.out\n"
      "{2}"
      "set -u\n"
      "{3}"
      "set --\n"
      "i=0\n"
      "while [ \"$i\" -lt \"$shards\" ]; do\n"
      "  set -- \"$@\" \"$dir/shard-$i\"\n"
      "  i=$((i + 1))\n"
      "done\n"
      "exec \"$strata\" campaign \"$spec\" --merge \"$@\" --out \"$dir/merged\"{4}\n",
      o.shards, o.job_name, shared_directives(o), assignments(o), quoted_words(o.spec_args));
  s.submit = fmt::format(
      "#!/bin/sh\n"
      "# Submits the campaign: the job array, then the merge once every task of\n"
      "# it succeeded. Written by `strata campaign --slurm` (--submit runs the same).\n"
      "set -eu\n"
      "dir={0}\n"
      "array=$(sbatch --parsable --chdir=\"$dir\" \"$dir/campaign.sbatch\")\n"
      "array=${{array%%;*}}\n"
      "merge=$(sbatch --parsable --chdir=\"$dir\" --dependency=afterok:\"$array\" \"$dir/merge.sbatch\")\n"
      "merge=${{merge%%;*}}\n"
      "echo \"array job $array ({1} tasks), merge job $merge: the merged results will be in $dir/merged\"\n",
      shell_quote(o.dir), o.shards);
  return s;
}

core::Result<void> write_slurm_scripts(const std::string& dir, const SlurmScripts& scripts) {
  if (auto made = make_real_dir(dir); !made) return made;
  std::error_code ec;
  if (!fs::is_empty(dir, ec) && !fs::exists(fs::symlink_status(fs::path(dir) / "campaign.sbatch", ec))) {
    return core::make_error(
        core::ErrorCode::Io,
        fmt::format("{}: a folder that is not empty and holds no campaign.sbatch; not writing a Slurm campaign "
                    "into it",
                    dir));
  }
  for (const auto& [name, text] :
       {std::pair{"campaign.sbatch", &scripts.array}, std::pair{"merge.sbatch", &scripts.merge},
        std::pair{"submit.sh", &scripts.submit}}) {
    if (auto r = write_out_file(dir, name, *text, 0755); !r) return r;
  }
  return {};
}

core::Result<std::string> parse_sbatch_job_id(std::string_view output) {
  std::string line(output.substr(0, output.find('\n')));
  line = trimmed(line.substr(0, line.find(';')));
  static const std::regex id(R"(\d+)");
  if (!std::regex_match(line, id)) {
    return invalid(fmt::format("no job id in sbatch's output '{}'", trimmed(std::string(output))));
  }
  return line;
}

SubmitProblem sbatch_problem(std::string_view sbatch_stderr) {
  // text-ok: sbatch's own messages (a third party's), the only account of why it failed
  if (sbatch_stderr.find("DNS SRV lookup failed") != std::string_view::npos ||
      sbatch_stderr.find("Could not establish a configuration source") != std::string_view::npos) {
    return SubmitProblem::NoCluster;
  }
  // text-ok: sbatch's own message (slurm_strerror of SLURMCTLD_COMMUNICATIONS_CONNECTION_ERROR)
  if (sbatch_stderr.find("Unable to contact slurm controller") != std::string_view::npos) {
    return SubmitProblem::NoController;
  }
  return SubmitProblem::Other;
}

core::Result<SlurmJobs, SubmitError> submit_slurm(const std::string& dir, const std::string& sbatch, double bound_s) {
  if (const char* conf = std::getenv("SLURM_CONF")) {
    std::error_code ec;
    if (!fs::is_regular_file(conf, ec)) {
      return submit_error(fmt::format("SLURM_CONF is '{}', which is no file (sbatch would try it for a minute)", conf),
                          SubmitProblem::NoCluster);
    }
  }
  const std::string chdir = "--chdir=" + dir;
  SlurmJobs jobs;
  auto array = sbatch_once({sbatch, "--parsable", chdir, (fs::path(dir) / "campaign.sbatch").string()}, bound_s);
  if (!array) return array.error();
  jobs.array_id = array.value();
  auto merge = sbatch_once(
      {sbatch, "--parsable", chdir, "--dependency=afterok:" + jobs.array_id, (fs::path(dir) / "merge.sbatch").string()},
      bound_s);
  if (!merge) {
    return submit_error(
        fmt::format("the array job {} was submitted, its merge was not: {}", jobs.array_id, merge.error().message),
        merge.error().problem);
  }
  jobs.merge_id = merge.value();
  return jobs;
}

std::string find_on_path(std::string_view name) {
  const char* path = std::getenv("PATH");
  if (!path || name.empty() || name.find('/') != std::string_view::npos) return {};
  std::istringstream folders(path);
  std::string folder;
  while (std::getline(folders, folder, ':')) {
    if (folder.empty()) folder = ".";
    const fs::path candidate = fs::absolute(fs::path(folder) / name);
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return {};
}

}  // namespace strata::campaign
