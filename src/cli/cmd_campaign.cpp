// `strata campaign SPEC`: every case of a campaign spec (docs/campaigns.md),
// run by a pool of worker processes, into a results folder.
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <thread>

#include <fmt/format.h>

#include "campaign/campaign_run.h"
#include "campaign/cases.h"
#include "campaign/compare.h"
#include "campaign/merge.h"
#include "campaign/case_run.h"
#include "campaign/slurm.h"
#include "campaign/spec.h"
#include "core/mission_language.h"
#include "cli/validators.h"
#include "cli/verbosity.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/signal_watcher.h"
#include "run/sonar_child.h"

namespace strata::cli {
namespace {

volatile std::sig_atomic_t g_stop_requests = 0;
volatile std::sig_atomic_t g_last_signal = 0;
extern "C" void on_campaign_signal(int sig) {
  g_last_signal = sig;
  g_stop_requests = g_stop_requests + 1;
}

// SIGINT, SIGTERM and SIGHUP count stop requests; no SA_RESTART, so the
// pool's poll() wakes at once.
void catch_stop_signals() {
  struct sigaction sa {};
  sa.sa_handler = on_campaign_signal;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &sa, nullptr);
}

struct CampaignFlags {
  VerbosityFlags verbosity;
  std::string spec;
  std::string out;
  int jobs = 0;
  bool list = false;
  std::optional<std::uint64_t> one_case;
  std::string cases;
  std::string keep_logs = "failed";
  std::uint64_t max_cases = campaign::kDefaultMaxCases;
  double case_wall_limit_s = 120.0;
  std::vector<std::string> compare;
  std::string shard;
  std::vector<std::string> merge;
  bool slurm = false;
  std::uint64_t shards = 16;
  bool submit = false;
  std::string partition;
  std::string time;
  std::vector<std::string> sbatch;
  std::string strata;
};

int list_cases(const campaign::Spec& spec, const std::vector<std::uint64_t>& indices) {
  for (std::uint64_t i : indices) {
    const campaign::Case c = campaign::case_at(spec, i);
    // A spec that perturbs the vehicle has one column more, on every line:
    // the parameters ("-" for a family that keeps the built-in ones).
    const std::string params =
        !spec.perturbs() ? "" : "\t" + (c.params.empty() ? std::string("-") : campaign::params_text(c));
    std::cout << fmt::format("{}\t{}\t{}\t{}{}\tseed {}\n", i, spec.missions[c.mission].path,
                             spec.families[c.family].name, campaign::fault_text(c), params, c.seed);
  }
  return static_cast<int>(kExitOk);
}

// --case I without --out: the case in this process, its result on stdout.
int run_one_case(const campaign::Spec& spec, std::uint64_t index) {
  const campaign::Case c = campaign::case_at(spec, index);
  campaign::CaseRunConfig config;
  config.keep_logs = campaign::KeepLogs::None;
  const auto line = campaign::run_case(spec, c, config);
  std::cout << fmt::format("case {}: {} · {} · {}{} · seed {}\n", index, spec.missions[c.mission].path,
                           spec.families[c.family].name, campaign::fault_text(c),
                           c.params.empty() ? "" : " · " + campaign::params_text(c), c.seed);
  std::cout << fmt::format("  outcome {}{}\n", line["outcome"].get<std::string>(),
                           line["reason"].get<std::string>().empty() ? "" : ": " + line["reason"].get<std::string>());
  for (const auto& check : line["checks"]) {
    std::cout << fmt::format("  {} {}: {}{}{}\n", check["pass"].get<bool>() ? "pass" : "FAIL",
                             check["name"].get<std::string>(), check["figure"].dump(),
                             check.contains("limit") ? " (limit " + check["limit"].dump() + ")" : "",
                             check.contains("note") ? " — " + check["note"].get<std::string>() : "");
  }
  std::cout << line.dump() << "\n";
  return static_cast<int>(line["pass"].get<bool>() ? kExitOk : kExitAbort);
}

// What to do when --submit found no Slurm to submit to, as a line before
// the error itself; "" for any other failure.
std::string submit_advice(const campaign::SubmitError& e, const std::string& dir) {
  const char* conf = std::getenv("SLURM_CONF");
  const std::string later = fmt::format("the scripts are written: {}/submit.sh submits them later", dir);
  const std::string recipe = "docs/campaigns.md, \"Slurm on one machine\"";
  switch (e.problem) {
    case campaign::SubmitProblem::NoCluster:
      return fmt::format(
          "sbatch found no Slurm cluster to submit to ({}). To try --submit on this machine, start a single-node "
          "Slurm with `scripts/slurm-local start` (as root) and export the SLURM_CONF it prints: {}; {}.\n  ",
          conf ? fmt::format("SLURM_CONF={} is no file", conf)
               : "SLURM_CONF is not set, and no /etc/slurm/slurm.conf or DNS SRV record names a controller",
          recipe, later);
    case campaign::SubmitProblem::NoController:
      return fmt::format(
          "sbatch could not reach the Slurm controller that {} names: is slurmctld running? For the single-node "
          "Slurm of scripts/slurm-local, `scripts/slurm-local status` says ({}); {}.\n  ",
          conf ? fmt::format("SLURM_CONF={}", conf) : "/etc/slurm/slurm.conf", recipe, later);
    case campaign::SubmitProblem::Other: break;
  }
  return "";
}

// --slurm: the job array and its merge written into --out (and submitted).
int write_slurm(const CampaignFlags& f, const CLI::App& cmd, std::uint64_t count) {
  namespace fs = std::filesystem;
  if (f.list || f.one_case || !f.cases.empty() || !f.shard.empty() || !f.merge.empty()) {
    std::cerr << "strata campaign: --slurm picks the shards itself; not with --list, --case, --cases, --shard or "
                 "--merge\n";
    return static_cast<int>(kExitUsage);
  }
  if (f.out.empty()) {
    std::cerr << "strata campaign: --slurm needs --out DIR (the scripts, the shards and merged/)\n";
    return static_cast<int>(kExitUsage);
  }
  campaign::SlurmOptions o;
  const bool shards_given = cmd.count("--shards") > 0;
  o.shards = shards_given ? f.shards : std::min<std::uint64_t>(f.shards, count);
  if (o.shards > count) {
    std::cerr << fmt::format("strata campaign: --shards {}: more shards than the spec's {} cases\n", o.shards, count);
    return static_cast<int>(kExitUsage);
  }
  std::error_code ec;
  o.spec = fs::absolute(f.spec, ec).lexically_normal().string();
  o.dir = fs::absolute(f.out, ec).lexically_normal().string();
  while (o.dir.size() > 1 && o.dir.back() == '/') o.dir.pop_back();
  o.strata = f.strata.empty() ? run::self_executable() : fs::absolute(f.strata, ec).lexically_normal().string();
  o.cpus_per_task = cmd.count("--jobs") > 0 ? f.jobs : 1;
  o.partition = f.partition;
  o.time = f.time;
  o.sbatch_args = f.sbatch;
  o.task_args = {"--keep-logs", f.keep_logs, "--case-wall-limit", fmt::format("{:g}", f.case_wall_limit_s)};
  if (cmd.count("--max-cases") > 0) o.spec_args = {"--max-cases", std::to_string(f.max_cases)};
  auto scripts = campaign::slurm_scripts(o);
  if (!scripts) {
    std::cerr << "strata campaign: " << scripts.error().message << "\n";
    return static_cast<int>(kExitUsage);
  }
  if (auto w = campaign::write_slurm_scripts(o.dir, scripts.value()); !w) {
    std::cerr << "strata campaign: " << w.error().message << "\n";
    return static_cast<int>(kExitIo);
  }
  std::cout << fmt::format("campaign {}: {} cases in {} Slurm array tasks ({} CPU{} each)\n", f.spec, count, o.shards,
                           o.cpus_per_task, o.cpus_per_task == 1 ? "" : "s");
  std::cout << fmt::format("  wrote {0}/campaign.sbatch, {0}/merge.sbatch, {0}/submit.sh\n", o.dir);
  if (!f.submit) {
    std::cout << fmt::format("  submit with: {}/submit.sh   (merged results: {}/merged)\n", o.dir, o.dir);
    return static_cast<int>(kExitOk);
  }
  const std::string sbatch = campaign::find_on_path("sbatch");
  if (sbatch.empty()) {
    std::cerr << fmt::format(
        "strata campaign: --submit: sbatch not found on PATH (install slurm-client, or run {}/submit.sh on a "
        "machine that has it)\n",
        o.dir);
    return static_cast<int>(kExitUnavailable);
  }
  auto jobs = campaign::submit_slurm(o.dir, sbatch);
  if (!jobs) {
    std::cerr << "strata campaign: --submit: " << submit_advice(jobs.error(), o.dir) << jobs.error().message << "\n";
    return static_cast<int>(kExitUnavailable);
  }
  std::cout << fmt::format("  submitted: array job {} ({} tasks), merge job {} after it (afterok)\n",
                           jobs.value().array_id, o.shards, jobs.value().merge_id);
  std::cout << fmt::format("  merged results: {}/merged; Slurm's output: {}/slurm-*.out\n", o.dir, o.dir);
  return static_cast<int>(kExitOk);
}

}  // namespace

Runner add_campaign_command(CLI::App& app) {
  auto f = std::make_shared<CampaignFlags>();
  auto* cmd = app.add_subcommand(
      "campaign",
      "Run every case of a campaign spec (missions x faults x injection times x seeds) against the simulated "
      "vehicle, check each against the spec's expectations, and write results.jsonl, report.json and "
      "report.html into --out. Exit 0: every case met its expectations; 1: some did not");
  cmd->add_option("spec", f->spec, "The campaign spec (TOML; docs/campaigns.md)");
  cmd->add_option("--compare", f->compare,
                  "Compare two campaigns' results.jsonl (A B): cases newly failing or passing, outcomes and figures "
                  "that changed; exit 1 when a verdict or an outcome changed")
      ->expected(2);
  cmd->add_option("--out", f->out, "The results folder (created; never written through a symbolic link)");
  cmd->add_option("-j,--jobs", f->jobs, "Worker processes (default: one per core)")->check(finite_range(1, 1024));
  cmd->add_flag("--list", f->list, "Print the cases, one a line (index, mission, family, fault, seed); run nothing");
  cmd->add_option("--case", f->one_case, "Run case I alone (in this process; with --out, into that folder)");
  cmd->add_option("--cases", f->cases, "Run the cases A-B (inclusive) only");
  cmd->add_option("--shard", f->shard, "Run every N-th case from the I-th (I/N, 0 <= I < N): one of N pieces");
  cmd->add_option("--merge", f->merge,
                  "Join the folders of runs of this spec's pieces (--shard, --cases) into --out: one results.jsonl "
                  "and one report, as a single run would give");
  cmd->add_option("--keep-logs", f->keep_logs, "Mission logs kept in DIR/logs: all, failed or none")
      ->check(CLI::IsMember({"all", "failed", "none"}))
      ->capture_default_str();
  cmd->add_option("--max-cases", f->max_cases, "The most cases a spec may make")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100'000'000}))
      ->capture_default_str();
  cmd->add_option("--case-wall-limit", f->case_wall_limit_s,
                  "Wall seconds one case may take before its worker is killed and the case reported crashed")
      ->check(finite_range(0.1, 86'400.0))
      ->capture_default_str();
  auto* slurm = cmd->add_flag(
      "--slurm", f->slurm,
      "Write a Slurm job array (task I runs --shard I/N into DIR/shard-I) and a merge job into DIR/merged that "
      "depends on it (afterok): DIR/campaign.sbatch, DIR/merge.sbatch, DIR/submit.sh, with DIR from --out; -j is "
      "each task's CPUs (default 1); runs nothing here unless --submit");
  cmd->add_option("--shards", f->shards, "With --slurm: array tasks, one shard each (default 16, at most the cases)")
      ->check(CLI::Range(std::uint64_t{1}, campaign::kMaxSlurmShards))
      ->needs(slurm);
  cmd->add_flag("--submit", f->submit,
                "With --slurm: submit the array and the merge with sbatch (from PATH) and print their job ids")
      ->needs(slurm);
  cmd->add_option("--partition", f->partition, "With --slurm: the partition of both jobs (default: the cluster's)")
      ->needs(slurm);
  cmd->add_option("--time", f->time,
                  "With --slurm: each job's time limit, in Slurm's forms (minutes, H:M:S, D-H:M:S; default: the "
                  "partition's)")
      ->needs(slurm);
  cmd->add_option("--sbatch", f->sbatch,
                  "With --slurm: one more #SBATCH option for both jobs, e.g. --sbatch=--account=ocean (repeatable)")
      ->allow_extra_args(false)
      ->needs(slurm);
  cmd->add_option("--strata", f->strata,
                  "With --slurm: the strata executable the jobs run, as the nodes see it (default: this one)")
      ->needs(slurm);
  add_verbosity_flags(cmd, f->verbosity, "");
  return [f, cmd] {
    if (!f->compare.empty()) {
      if (!f->spec.empty()) {
        std::cerr << "strata campaign: --compare takes two results files and no spec\n";
        return static_cast<int>(kExitUsage);
      }
      auto r = campaign::compare_results(f->compare[0], f->compare[1]);
      if (!r) {
        std::cerr << "strata campaign: " << r.error().message << "\n";
        return exit_code_for_input(r.error());
      }
      std::cout << campaign::compare_text(r.value(), f->compare[0], f->compare[1]);
      return static_cast<int>(r.value().differs() ? kExitAbort : kExitOk);
    }
    if (f->spec.empty()) {
      std::cerr << "strata campaign: a spec is needed (or --compare A.jsonl B.jsonl)\n";
      return static_cast<int>(kExitUsage);
    }
    if (core::mission_language(f->spec) != core::MissionLanguage::None) {
      std::cerr << fmt::format(
          "strata campaign: '{}' is a mission, not a campaign spec (a .toml file: "
          "docs/campaigns.md); `strata run {}` runs it once\n",
          f->spec, f->spec);
      return static_cast<int>(kExitUsage);
    }
    auto spec = campaign::load_spec(f->spec, {f->max_cases});
    if (!spec) {
      std::cerr << "strata campaign: " << spec.error().message << "\n";
      return exit_code_for_input(spec.error());
    }
    const std::uint64_t count = spec.value().case_count();
    if (f->slurm) return write_slurm(*f, *cmd, count);
    if (!f->merge.empty()) {
      if (f->out.empty()) {
        std::cerr << "strata campaign: --merge needs --out DIR\n";
        return static_cast<int>(kExitUsage);
      }
      auto merged = campaign::merge_campaigns(spec.value(), f->merge, f->out,
                                              fmt::format("strata campaign {} --merge ... --out {}", f->spec, f->out));
      if (!merged) {
        std::cerr << "strata campaign: " << merged.error().message << "\n";
        return exit_code_for_input(merged.error());
      }
      const auto& m = merged.value();
      std::cout << fmt::format("campaign {}: merged {} folders: {} of {} cases, {} passed, {} failed{}\n", f->spec,
                               f->merge.size(), m.done, m.planned, m.done - m.failed, m.failed,
                               m.duplicates ? fmt::format(" ({} duplicates dropped)", m.duplicates) : "");
      if (m.done < m.planned) std::cout << fmt::format("  {} cases missing\n", m.planned - m.done);
      return static_cast<int>(m.failed == 0 && m.done == m.planned ? kExitOk : kExitAbort);
    }
    std::vector<std::uint64_t> indices;
    if (!f->shard.empty()) {
      if (f->one_case || !f->cases.empty()) {
        std::cerr << "strata campaign: --shard picks its own cases; not with --case or --cases\n";
        return static_cast<int>(kExitUsage);
      }
      auto picked = campaign::shard_indices(f->shard, count);
      if (!picked) {
        std::cerr << "strata campaign: " << picked.error().message << "\n";
        return static_cast<int>(kExitUsage);
      }
      indices = std::move(picked).value();
    } else if (f->one_case || !f->cases.empty()) {
      if (f->one_case && !f->cases.empty()) {
        std::cerr << "strata campaign: give --case or --cases, not both\n";
        return static_cast<int>(kExitUsage);
      }
      auto range = campaign::parse_range(f->one_case ? std::to_string(*f->one_case) : f->cases, count);
      if (!range) {
        std::cerr << "strata campaign: " << range.error().message << "\n";
        return static_cast<int>(kExitUsage);
      }
      for (std::uint64_t i = range.value().first; i <= range.value().last; ++i) indices.push_back(i);
    } else {
      indices.reserve(count);
      for (std::uint64_t i = 0; i < count; ++i) indices.push_back(i);
    }
    if (f->list) return list_cases(spec.value(), indices);
    if (f->one_case && f->out.empty()) return run_one_case(spec.value(), *f->one_case);
    if (f->out.empty()) {
      std::cerr << "strata campaign: --out DIR is needed to run a campaign (or --list, or --case I)\n";
      return static_cast<int>(kExitUsage);
    }
    campaign::CampaignOptions o;
    o.out_dir = f->out;
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    o.jobs = f->one_case ? 0 : (cmd->count("--jobs") > 0 ? f->jobs : static_cast<int>(cores));
    o.keep_logs = f->keep_logs == "all"    ? campaign::KeepLogs::All
                  : f->keep_logs == "none" ? campaign::KeepLogs::None
                                           : campaign::KeepLogs::Failed;
    o.case_wall_limit_s = f->case_wall_limit_s;
    o.command = fmt::format("strata campaign {} --out {}", f->spec, f->out);
    o.progress = f->verbosity.level() == Verbosity::Quiet ? nullptr : &std::cerr;
    o.progress_tty = ::isatty(STDERR_FILENO) == 1;
    o.stop_requests = &g_stop_requests;
    catch_stop_signals();
    auto ran = campaign::run_campaign(spec.value(), indices, o);
    if (!ran) {
      std::cerr << "strata campaign: " << ran.error().message << "\n";
      return static_cast<int>(kExitIo);
    }
    const campaign::CampaignOutcome& r = ran.value();
    std::cout << fmt::format("campaign {}: {} of {} cases ran, {} passed, {} failed ({:.1f} s, {:.1f} cases/s)\n",
                             spec.value().name.empty() ? f->spec : spec.value().name, r.done, r.planned,
                             r.done - r.failed, r.failed, r.wall_s,
                             r.wall_s > 0 ? static_cast<double>(r.done) / r.wall_s : 0.0);
    std::cout << fmt::format("  results: {0}/results.jsonl, report: {0}/report.html\n", f->out);
    if (r.past_proven_bound > 0) {
      std::cout << fmt::format(
          "  {} cases took longer than the proven bound: the timing analysis is unsound for them (report.json, "
          "\"bounds\")\n",
          r.past_proven_bound);
    }
    if (r.interrupted) {
      std::cout << fmt::format("  interrupted by {}: the finished cases are kept\n", signal_name(g_last_signal));
      return kExitSignalBase + static_cast<int>(g_last_signal);
    }
    return static_cast<int>(r.failed == 0 ? kExitOk : kExitAbort);
  };
}

}  // namespace strata::cli
