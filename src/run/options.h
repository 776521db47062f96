#pragma once
// What one run is given: its inputs, the vehicle to run against, and its
// limits. Plain data; the CLI fills it from flags, the studio from a request.
#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/result.h"

namespace strata::run {

// PROLOG: the limits on loading and checking the rules (strategic::LoadLimits).
struct RuleLoadLimits {
  double time_s = 5.0;                    // wall clock of the load and check together
  std::uint64_t inferences = 50'000'000;  // clauses read and directives run, together
  std::uint64_t max_bytes = 4u << 20;     // each rule file
};

struct RunOptions {
  std::string mission;   // a .coral (CORAL) or .pl (PROLOG) file
  std::string data;      // overrides the mission's data file
  std::string scenario;  // name (in the mission's scenarios/) or path; "" nominal
  std::string params;    // vehicle parameter file; "" built in
  // Vehicle parameters set over `params` (or the built-in values), each by
  // its name in config/phoenix.toml ("hull.mass_kg") and checked as the
  // file's are (vehicle::set_param): a campaign's perturbations. Embedded
  // vehicle only.
  std::vector<std::pair<std::string, double>> param_overrides;
  std::string catalogue;                       // primitive catalogue; "" built in
  std::optional<std::uint64_t> seed;           // CORAL: seeded choice among enabled transitions
  std::uint64_t inference_limit = 10'000'000;  // PROLOG: inferences allowed between primitive calls
  RuleLoadLimits rule_load;                    // PROLOG: loading and checking the rules
  bool realtime = false;                       // the embedded vehicle on the wall clock
  double speed = 1.0;                          // with realtime: simulated seconds per wall second
  std::string vehicle;                         // HOST:PORT of a running vehicle; "" embedded
  // The mission log: this file (created, or a regular file replaced; never
  // through a link), or else a new dated file in log_dir
  // (tactical::dated_log_name); both "": none. The run creates it once,
  // after the inputs load: a run that never loads leaves no file.
  std::string log;
  std::string log_dir;
  // The mission log written to this stream instead (the caller owns it and
  // keeps it open past run(); `log` then only names it in the report). The
  // studio opens its logs itself, inside its folder, never through a link.
  std::ostream* log_stream = nullptr;
  // When set, every input file the run reads itself — the CORAL mission and
  // its imports, the mission data file, the scenario file — is read through
  // this (path as the run names it, absolute or relative to the process),
  // never opened by name: the studio passes its folder's sandbox, so a file
  // swapped for a link after the studio checked it is still refused. An
  // error's message is shown as the reason the input could not be read.
  // Not used for PROLOG rules (SWI-Prolog opens them itself), --params or
  // --catalogue.
  std::function<core::Result<std::string>(const std::string& path)> read_file;
  // Start the Sonar Manager (`strata sonar`, a separate process) on the
  // vehicle's sonar socket, writing its scans here; "" none.
  std::string sonar_dir;
  double telemetry_hz = 2.0;  // telemetry asked of the vehicle, per simulated second
  bool trace = false;         // keep every primitive call in RunReport::trace (strata compare)
  // The mission may be taken back from an earlier run in this process: a
  // campaign's worker, which runs one mission case after case. PROLOG: the
  // rules stay loaded after this run (strategic::KeepRules::Yes). CORAL:
  // the mission compiled and verified is kept, and taken back while every
  // file its compile read (the mission, its imports, the library folders'
  // lookups) reads the same, with the same catalogue and vehicle.
  bool keep_mission = false;
  // PROLOG, without keep_mission: rules this process loaded for an earlier
  // run are taken back, put back as they were right after their load, when
  // taking them back is the same as loading them again: the same files,
  // unchanged, whose directives only declare predicates and load files
  // (strategic::KeepRules::Reproducible). A run in the studio, or the next
  // of a program that runs missions. false: loaded afresh every time.
  bool reuse_rules = true;
  // CORAL: a mission that fails verification (docs/verification.md) is not
  // run unless this is set; then it runs and the log records the failures.
  bool unverified = false;
  // A script of vehicle answers (run/answers.h; `strata verify
  // --witness-out` writes one): the calls it names get its answers, the
  // vehicle still carries them out. Read through read_file when set. A
  // mission that fails verification runs with it, as with `unverified`.
  std::string answers;
  // Lockstep (and over IMC, on the vehicle's clock): simulated seconds after which the run is ended (an abort, by
  // the safe end) whatever the mission is doing. A day by default: a tank or
  // harbour mission takes minutes; a loop of sleep(1) would otherwise run,
  // and log, until the disk is full.
  double max_sim_time_s = 86'400.0;
  // The mission log's size: past it (less a reserve for its last records)
  // the run ends as at a limit, the vehicle surfaced by the safe end, and
  // later lines are dropped. 0: no bound. A tank run logs about 200 KB, an
  // hour's survey at 10 Hz telemetry a few MB; a mission that restarts a
  // phase in a loop logged 127 MB in 25 s.
  std::uint64_t max_log_bytes = std::uint64_t{256} << 20;
  // Every line on the link (see tactical::LinkOptions::tap); for benchmarks.
  std::function<void(bool sent, std::string_view line)> wire_tap;
};

}  // namespace strata::run
