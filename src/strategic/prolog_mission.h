#pragma once
// A PROLOG mission (paper §2.2, Figure 10; docs/prolog.md): rules
// loaded into a module of their own, beside one predicate per vehicle
// primitive of the catalogue, and checked before they run. The Prolog side
// of this lives in prolog/driver*.pl (driver.pl, driver_load.pl,
// driver_sandbox.pl, driver_check.pl, driver_keep.pl), compiled
// into the binary; it runs on src/prolog's engine (prolog/engine.h).
// The names stay in strata::prolog (PrologMission, PrologHost...), as
// before the driver moved here from src/prolog.
//
// One mission runs at a time per process (SWI-Prolog has one engine here):
// while a PrologMissionQuery is open, no other Prolog may run.
//
// Threads: the one that called prolog::initialise(); load() on another
// returns an error.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostic.h"
#include "core/result.h"
#include "core/source.h"
#include "prolog/engine.h"
#include "tactical/catalogue.h"
#include "tactical/execution_level.h"
#include "tactical/value.h"

namespace strata::strategic {

struct PrologMessage;  // the driver's own (prolog_messages.h)

// A guard's condition, one term: ask `ask` (with its literal arguments);
// it trips the guard when answered 1, or 0 when negated (`not(q)`).
struct GuardTerm {
  std::string ask;
  std::vector<tactical::Value> args;
  bool negated = false;
  std::string text;  // as the log says it: "system_problem", "not gps_available", "depth_below(10)"
};

// A guard as the rules declare it (guard/4, phase_guard/5; docs/prolog.md
// §8), its handler left on the Prolog side.
struct GuardSpec {
  std::string name;
  double period_s = 1.0;
  std::vector<GuardTerm> terms;  // asked in order; never empty
};

// A tripped guard, as the rules see it: strata_guard_trip(Scope, Guard).
struct GuardTripSignal {
  std::uint64_t scope = 0;
  std::string guard;
};

// What the rules reach while they run. The executor implements it.
class PrologHost {
 public:
  virtual ~PrologHost() = default;
  // A primitive call (exec, ask, ood); the query yields right after.
  virtual void primitive(const std::string& name, std::vector<tactical::Value> args) = 0;
  // On resuming: the answer to unify with the rules' variable (1 or 0), or
  // nullopt to raise strata_cancelled in the rules instead.
  virtual std::optional<int> answer() = 0;
  // A REPORT: not waited for.
  virtual void report(const std::string& name, std::vector<tactical::Value> args) = 0;
  // execute_phase(P) started, and ended: exit is complete, abort, done or failed.
  virtual void phase_started(const std::string& phase) = 0;
  virtual void phase_ended(const std::string& phase, const std::string& exit) = 0;
  // Guards (docs/prolog.md §8). A host that polls none (the defaults) runs
  // guarded rules as if they had no guards.
  // A guarded scope (mission/0 with guard/4 facts, or a phase with
  // phase_guard/5 facts) opens: its guards, in declaration order. Returns
  // the scope's id (never 0).
  virtual std::uint64_t open_guards(const std::vector<GuardSpec>& /*guards*/) { return 1; }
  // It closes (normally, by an exception, or unwound by its own trip): the
  // guard that tripped it, if one did. An unknown id (a scope an outer
  // trip pre-empted) gives nullopt.
  virtual std::optional<std::string> close_guards(std::uint64_t /*scope*/) { return std::nullopt; }
  // Between a guard's trip and the close of its scope: the trip, which the
  // rules raise in place of an answer and of every call they make meanwhile.
  virtual std::optional<GuardTripSignal> pending_trip() const { return std::nullopt; }
  // A primitive the rules called while a trip was pending: not called.
  virtual void call_not_made(const std::string& /*name*/) {}
};

// The limits on loading and checking rules (directives included): past
// either, the load ends with a located error. Standard input is never read
// (the sandbox refuses read/1 and the like).
struct LoadLimits {
  std::chrono::milliseconds time{5000};   // wall clock of the load and the check together
  std::uint64_t inferences = 50'000'000;  // the load: clauses read and directives run, together
  std::size_t max_bytes = 4u << 20;       // each rule file; a larger one is not read
};

// Whether PrologMission::load may take back rules it loaded before (a campaign's
// worker runs one mission's rules case after case).
//  - No: the files are loaded and checked again.
//  - Yes: rules that loaded and checked without an error stay loaded when
//    their PrologMission ends (one set per process). The next load with the same
//    path, catalogue and limits, while every file they loaded holds what it
//    held then, takes them back instead of loading them again: each dynamic
//    predicate gets back its clauses of right after the load, and the
//    dynamic predicates the rules created as they ran are removed, so a run
//    sees what it would see after a fresh load (prolog/driver_keep.pl).
//    Rules whose state could not be put back so (tabled or thread-local
//    predicates; calls to set_prolog_flag/2, set_prolog_stack/2,
//    predicate_property/2, global variables) are loaded afresh every time,
//    as are rules another PrologMission still has. What the
//    directives computed is not computed again: get_time/1 in a directive
//    gives the first load's time. The messages are the first load's.
//  - Reproducible: as Yes, for rules whose second load would do what their
//    first did: every directive only declared predicates or loaded files
//    (prolog/driver_keep.pl, reproducible_mission/1), and every file name
//    the load resolved still names the same file. Taking them back is then
//    the same as loading them again; other rules are loaded every time,
//    their directives run again. For runs outside a campaign.
enum class KeepRules { No, Yes, Reproducible };

class PrologMission {
 public:
  // Loads the rules at path (and the files they load) with the primitives
  // of catalogue, then checks them: for a vehicle at `level` too, whose
  // check refuses every call, in any of those files, of a primitive it
  // cannot carry out (PrimitiveUnavailable, at the call).
  // Every problem (warnings too) goes to sink as a core::Diagnostic, as
  // CORAL's do (PrologLoadError, PrologLoadWarning, PrologCheckError,
  // ArgumentOutOfRange, PrimitiveUnavailable, FileTooLarge), in the order
  // found; each file they name is added to sources, with its text.
  // Errors: Io when path cannot be read, Internal when the driver cannot
  // start (neither reported to sink); InvalidInput when an error was.
  static core::Result<std::unique_ptr<PrologMission>> load(
      const std::string& path, const tactical::Catalogue& catalogue, core::SourceManager& sources,
      core::DiagnosticSink& sink, const LoadLimits& limits = {}, KeepRules keep = KeepRules::No,
      tactical::ExecutionLevel level = tactical::ExecutionLevel::Phoenix);
  ~PrologMission();
  PrologMission(const PrologMission&) = delete;
  // The process ends after this mission, and loads no other rules: its
  // module is not closed when it is destroyed (closing it, about half a
  // millisecond of a `strata check`, would be undone by the exit anyway).
  void leave_open_to_exit() { module_.clear(); }
  PrologMission& operator=(const PrologMission&) = delete;

  const std::string& path() const { return path_; }
  const std::string& name() const { return name_; }  // the file's stem: "tank"
  const std::string& module() const { return module_; }
  // The mission data file named by a mission_data/1 fact, resolved against
  // the mission's folder; "" when the rules name none.
  const std::string& data_file() const { return data_file_; }
  // A PrologMissionQuery has run the rules: the facts they asserted stay, so a
  // new run needs a new load (with KeepRules::Yes, perhaps the same rules
  // taken back).
  bool started() const { return started_; }

 private:
  friend class PrologMissionQuery;
  PrologMission() = default;
  // load(), with the problems as the driver collects them.
  static core::Result<std::unique_ptr<PrologMission>> load_collecting(const std::string& path,
                                                                      const tactical::Catalogue& catalogue,
                                                                      std::vector<PrologMessage>& messages,
                                                                      const LoadLimits& limits, KeepRules keep,
                                                                      tactical::ExecutionLevel level);
  std::string path_, name_, module_, data_file_;
  bool started_ = false;
  bool kept_ = false;  // kept loaded when this ends (KeepRules::Yes)
};

// mission/0 running: next() runs the rules until they call a primitive
// (Yield: host.primitive() has the call; answer it with host.answer() on
// the next next()), finish (True), fail (False) or raise (Exception).
class PrologMissionQuery {
 public:
  // inference_limit: inferences allowed between two primitive calls.
  PrologMissionQuery(PrologMission& mission, PrologHost& host, std::uint64_t inference_limit);
  ~PrologMissionQuery();
  PrologMissionQuery(const PrologMissionQuery&) = delete;
  PrologMissionQuery& operator=(const PrologMissionQuery&) = delete;

  prolog::Query::Status next();
  // After Status::Exception: the exception's text (for a stop the rules
  // could not catch, its cause), without the mission's module name.
  const std::string& exception_text() const { return exception_; }
  // The exception was strata_halt or strata_halt(Code): Code (0 for halt/0).
  std::optional<int> halted() const { return halted_; }
  bool inference_limit_exceeded() const { return limit_exceeded_; }
  bool out_of_stack() const { return out_of_stack_; }
  // A primitive was called where Prolog cannot suspend (a cleanup handler,
  // with_output_to/2, format/2's ~@).
  bool cannot_suspend() const { return cannot_suspend_; }
  // interrupt_rules() stopped the rules (the exception is strata_interrupted).
  bool interrupted() const { return interrupted_; }
  // Ends the query; next() may not be called after.
  void close();

 private:
  PrologMission& mission_;
  PrologHost& host_;
  fid_t frame_ = 0;
  std::unique_ptr<prolog::Query> query_;
  std::optional<int> halted_;
  bool limit_exceeded_ = false;
  bool out_of_stack_ = false;
  bool cannot_suspend_ = false;
  bool interrupted_ = false;
  std::string exception_;
};

// From any thread (prolog/interrupt.h): stops the rules of the PrologMissionQuery
// whose host is host while its next() runs them; next() then returns
// Status::Exception with interrupted() set, soon (at the rules' next call,
// or as sleep/1 returns), whatever the rules catch. Returns false and does
// nothing when they do not run (they wait for an answer, or no query of
// host is open): the next next() runs them as usual.
bool interrupt_rules(const PrologHost& host);

// After mission/0 succeeded or halted: aborted when the rules left
// current_phase(mission_abort) (Figure 10's `done`), completed otherwise.
enum class RulesOutcome { Completed, Aborted };
core::Result<RulesOutcome> mission_outcome(const PrologMission& mission);

}  // namespace strata::strategic
