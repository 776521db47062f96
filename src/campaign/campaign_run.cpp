#include "campaign/campaign_run.h"

#include <chrono>
#include <optional>

#include <fmt/format.h>

#include "campaign/bound.h"
#include "campaign/output.h"
#include "campaign/pool.h"
#include "campaign/report_html.h"
#include "campaign/summary.h"

namespace strata::campaign {
namespace {

using Clock = std::chrono::steady_clock;

class Progress {
 public:
  Progress(std::ostream* out, bool tty, std::uint64_t total) : out_(out), tty_(tty), total_(total) {}

  void update(std::uint64_t done, std::uint64_t failed, bool force = false) {
    if (out_ == nullptr) return;
    const auto now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
    const std::string line =
        fmt::format("campaign: {}/{} cases, {:.1f} cases/s, {} failed", done, total_, rate, failed);
    if (tty_) {
      if (!force && now - last_ < std::chrono::milliseconds(100)) return;
      *out_ << "\r\033[K" << line << std::flush;
      drawn_ = true;
    } else {
      const std::uint64_t tenth = total_ >= 10 ? total_ / 10 : 1;
      const bool step = done / tenth != last_done_ / tenth;
      if (!force && !step && now - last_ < std::chrono::seconds(5)) return;
      if (done == last_done_ && !force) return;
      *out_ << line << "\n" << std::flush;
    }
    last_ = now;
    last_done_ = done;
  }
  void finish(std::uint64_t done, std::uint64_t failed) {
    if (out_ == nullptr) return;
    if (tty_) {
      update(done, failed, true);
      if (drawn_) *out_ << "\n" << std::flush;
    } else if (done != last_done_) {
      update(done, failed, true);
    }
  }

 private:
  std::ostream* out_;
  bool tty_;
  std::uint64_t total_;
  Clock::time_point start_ = Clock::now();
  Clock::time_point last_ = start_;
  std::uint64_t last_done_ = 0;
  bool drawn_ = false;
};

}  // namespace

core::Result<CampaignOutcome> run_campaign(const Spec& spec, const std::vector<std::uint64_t>& indices,
                                           const CampaignOptions& options) {
  if (auto r = prepare_out_dir(options.out_dir); !r) return r.error();
  auto results = ResultsFile::create(options.out_dir);
  if (!results) return results.error();
  Summary summary(spec);
  for (const Mission& m : spec.missions) {
    if (m.kind != MissionKind::Coral) continue;
    // A mission that does not compile shows in its cases ("error"); here it
    // only leaves coverage without the list of transitions.
    if (auto names = mission_transitions(m.resolved)) summary.set_transitions(m.path, std::move(names).value());
  }
  // The bounds, proven here once before the workers fork: they inherit
  // the answers (campaign/bound.h keeps them) instead of each proving them.
  for (std::size_t m = 0; m < spec.missions.size(); ++m) {
    for (const Family& f : spec.families) {
      const ExpectationSet& set = spec.expectations.at(f.expect);
      if (set.bound && f.applies_to(m)) (void)proven_bound(spec, m, set, spec.base_params);
    }
  }
  CaseRunConfig config;
  config.out_dir = options.out_dir;
  config.keep_logs = options.keep_logs;
  Progress progress(options.progress, options.progress_tty, indices.size());
  std::optional<core::Error> write_error;
  PoolOptions pool;
  pool.workers = std::max(1, options.jobs);
  pool.case_wall_limit_s = options.case_wall_limit_s;
  pool.stop_requests = options.stop_requests;
  pool.on_result = [&](const nlohmann::ordered_json& line) {
    summary.add(line);
    if (auto r = results.value().append(line); !r && !write_error) write_error = r.error();
  };
  pool.on_tick = [&] { progress.update(summary.done(), summary.failed()); };
  const auto start = Clock::now();
  const PoolOutcome ran =
      options.jobs == 0 ? run_inline(spec, indices, config, pool) : run_pool(spec, indices, config, pool);
  progress.finish(summary.done(), summary.failed());
  CampaignOutcome out;
  out.planned = indices.size();
  out.done = summary.done();
  out.failed = summary.failed();
  out.interrupted = ran.stopped;
  out.past_proven_bound = summary.past_proven_bound();
  out.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  if (write_error) return *write_error;
  CampaignRun run{out.planned, pool.workers, out.wall_s, out.interrupted, options.command};
  const nlohmann::ordered_json report = summary.to_json(run);
  if (auto r = write_out_file(options.out_dir, "report.json", report.dump(2) + "\n"); !r) return r.error();
  if (auto r = write_out_file(options.out_dir, "report.html", report_html(report)); !r) return r.error();
  return out;
}

}  // namespace strata::campaign
