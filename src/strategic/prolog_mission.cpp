#include "strategic/prolog_mission.h"

#include <algorithm>
#include <cctype>
#include <iterator>
#include <memory>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "core/file.h"
#include "core/diagnostic.h"
#include "strategic/prolog_driver.h"
#include "strategic/prolog_messages.h"
#include "strategic/prolog_rules_args.h"
#include "prolog/interrupt.h"
#include "tactical/sha256.h"

namespace strata::strategic {
namespace {

namespace fs = std::filesystem;

using prolog_detail::call_driver;
using prolog_detail::call_driver_keep;
using prolog_detail::driver_goal;
using prolog_detail::new_atom;

std::string prolog_atom(std::string_view s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'' || c == '\\') out += '\\';
    out += c;
  }
  return out + "'";
}

std::string primitive_specs(const tactical::Catalogue& catalogue) {
  std::string out = "[";
  for (const auto& p : catalogue.all()) {
    if (out.size() > 1) out += ",";
    out += fmt::format("primitive({},{},{},{})", prolog_atom(p.name), core::call_verb_name(p.kind), p.min_args(),
                       p.max_args());
  }
  return out + "]";
}

// A file as the user would name it: relative to the current folder when inside it.
std::string shown_path(const std::string& file) {
  if (file.empty()) return file;
  std::error_code ec;
  fs::path rel = fs::proximate(file, ec);
  return ec || rel.empty() || rel.native().starts_with("..") ? file : rel.string();
}

std::uint32_t get_uint(term_t t) {
  int64_t v = 0;
  return PL_get_int64(t, &v) && v > 0 ? static_cast<std::uint32_t>(v) : 0;
}

// SWI names predicates with their module; the mission's own is noise.
std::string without_module(std::string text, const std::string& module) {
  const std::string prefix = module + ":";
  for (std::size_t at; (at = text.find(prefix)) != std::string::npos;) text.erase(at, prefix.size());
  return text;
}

void collect_load_messages(const std::string& module, const std::string& root, std::vector<PrologMessage>& out) {
  prolog::Frame frame;
  term_t a = PL_new_term_refs(5);
  term_t goal = driver_goal("load_message", {a, a + 1, a + 2, a + 3, a + 4});
  prolog::Query q(goal, false);
  while (true) {
    auto s = q.next();
    if (s != prolog::Query::Status::True && s != prolog::Query::Status::Last) break;
    PrologMessage m;
    m.kind =
        prolog::text_of(a) == "error" ? core::DiagnosticKind::PrologLoadError : core::DiagnosticKind::PrologLoadWarning;
    m.file = shown_path(prolog::text_of(a + 1));
    if (m.file.empty()) m.file = root;  // SWI gave no place: the mission's file
    m.line = get_uint(a + 2);
    m.column = get_uint(a + 3);
    m.text = without_module(prolog::text_of(a + 4), module);
    out.push_back(std::move(m));
    if (s == prolog::Query::Status::Last) break;
  }
}

// The driver's check: undefined calls (unknown primitives among them) and a
// missing mission/0.
void check_rules(const PrologMission& mission, std::vector<PrologMessage>& messages) {
  term_t problems = PL_new_term_ref();
  auto checked = call_driver("check_mission", {new_atom(mission.module()), problems});
  if (!checked || !checked.value()) {
    messages.push_back(
        {core::DiagnosticKind::PrologCheckError, mission.path(), 0, 0,
         "the rules could not be checked: " + (checked ? std::string("failed") : checked.error().message)});
  } else {
    term_t head = PL_new_term_ref();
    term_t arg = PL_new_term_ref();
    term_t tail = PL_copy_term_ref(problems);
    while (PL_get_list(tail, head, tail)) {
      PrologMessage m;
      m.kind = core::DiagnosticKind::PrologCheckError;
      PL_get_arg(1, head, arg);
      m.file = shown_path(prolog::text_of(arg));
      if (m.file.empty()) m.file = mission.path();
      PL_get_arg(2, head, arg);
      // Line, or Line:Column for a call the sandbox refused.
      term_t line = PL_new_term_ref();
      term_t column = PL_new_term_ref();
      if (PL_is_functor(arg, PL_new_functor(PL_new_atom(":"), 2)) && PL_get_arg(1, arg, line) &&
          PL_get_arg(2, arg, column)) {
        m.line = get_uint(line);
        m.column = get_uint(column);
      } else {
        m.line = get_uint(arg);
      }
      PL_get_arg(3, head, arg);
      m.text = prolog::text_of(arg);
      messages.push_back(std::move(m));
    }
  }
}

// Every call of a primitive that a vehicle at `level` cannot carry out, in
// the mission's own file and every file it loaded, at the call.
void check_level(const PrologMission& mission, const tactical::Catalogue& catalogue, tactical::ExecutionLevel level,
                 std::size_t max_bytes, std::vector<PrologMessage>& messages) {
  if (level == tactical::ExecutionLevel::Phoenix) return;
  // Each file once, however its path is spelt (SWI-Prolog's, or through a link).
  auto same_file = [](const std::string& path) {
    std::error_code ec;
    fs::path p = fs::weakly_canonical(path, ec);
    return ec ? path : p.string();
  };
  std::vector<std::string> files{mission.path()};
  std::vector<std::string> seen{same_file(mission.path())};
  prolog::Frame frame;
  term_t loaded = PL_new_term_ref();
  if (auto r = call_driver_keep("mission_files", {new_atom(mission.module()), loaded}); r && r.value()) {
    term_t head = PL_new_term_ref();
    term_t tail = PL_copy_term_ref(loaded);
    while (PL_get_list(tail, head, tail)) {
      std::string file = prolog::text_of(head);
      std::string key = same_file(file);
      if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
      seen.push_back(std::move(key));
      files.push_back(shown_path(file));
    }
  }
  for (const auto& shown : files) {
    auto text = core::read_regular_file(shown, max_bytes);
    if (!text) continue;  // the load read it: a file gone since holds no call
    for (auto& p : scan_unavailable_primitives(text.value(), catalogue, level)) {
      messages.push_back({core::DiagnosticKind::PrimitiveUnavailable, shown, static_cast<std::uint32_t>(p.line),
                          static_cast<std::uint32_t>(p.column), std::move(p.text)});
    }
  }
}

// A wall-clock limit on the Prolog that runs on this thread while it lives:
// past it, a watchdog thread interrupts it (prolog/interrupt.h: also out of
// sleep/1), again every 50 ms, since a directive's catch/3 could swallow one
// raise when the query runs without the driver's exception hook. The end
// does not wait for the watchdog: it tells it, under the lock the watchdog
// interrupts under, and leaves it to end on its own (joining it cost a
// wake-up of that thread at every load: milliseconds of wall clock on a busy
// machine, most of a repeated load's).
class TimeLimit {
 public:
  explicit TimeLimit(std::chrono::milliseconds limit) : scope_(this), state_(std::make_shared<State>()) {
    std::thread([state = state_, owner = static_cast<const void*>(this), limit] {
      std::unique_lock lock(state->mutex);
      if (state->done_cv.wait_for(lock, limit, [&state] { return state->done; })) return;
      state->expired = true;
      while (!state->done) {
        prolog::interrupt(owner);
        state->done_cv.wait_for(lock, std::chrono::milliseconds(50), [&state] { return state->done; });
      }
    }).detach();
  }
  // After this, the watchdog interrupts nothing: it sees `done` at once
  // when it holds the lock, else the next time it takes it.
  ~TimeLimit() {
    {
      std::lock_guard lock(state_->mutex);
      state_->done = true;
    }
    state_->done_cv.notify_all();
  }
  TimeLimit(const TimeLimit&) = delete;
  TimeLimit& operator=(const TimeLimit&) = delete;

  bool expired() {
    std::lock_guard lock(state_->mutex);
    return state_->expired;
  }

 private:
  // Shared with the watchdog, which may outlive this.
  struct State {
    std::mutex mutex;
    std::condition_variable done_cv;
    bool done = false;
    bool expired = false;
  };
  prolog::InterruptScope scope_;
  std::shared_ptr<State> state_;
};

// Rules kept loaded after their PrologMission ended (KeepRules::Yes): one set
// per process, taken back by the next load of the same files.
struct KeptRules {
  std::string key;  // the path as given and in full, the catalogue, the limits
  std::string module;
  std::vector<std::pair<std::string, std::string>> files;  // each file loaded, and the SHA-256 of what it held
  std::vector<PrologMessage> messages;                     // the load's (warnings)
  std::string data_file;
  bool reproducible = false;  // may be taken back by KeepRules::Reproducible
  bool in_use = false;        // a PrologMission has them
};
std::optional<KeptRules> g_kept;

// The current folder too: the messages name files relative to it.
std::string kept_key(const std::string& path, const std::string& absolute, const std::string& specs,
                     const LoadLimits& limits, tactical::ExecutionLevel level) {
  std::error_code ec;
  return fmt::format("{}\n{}\n{}\n{}\n{} {} {}\n{}", path, absolute, fs::current_path(ec).string(), specs,
                     limits.time.count(), limits.inferences, limits.max_bytes, tactical::execution_level_name(level));
}

std::string content_sha256(const std::string& file, std::size_t max_bytes) {
  auto text = core::read_regular_file(file, max_bytes);
  return text ? tactical::sha256_hex(text.value()) : std::string();
}

// The kept rules are no longer: their module goes, as a PrologMission's does.
void close_kept() {
  prolog::Frame frame;
  term_t module = new_atom(g_kept->module);
  (void)call_driver_keep("forget_kept", {module});
  (void)call_driver("close_mission", {module});
  g_kept.reset();
}

// The kept rules of key, put back as they were right after their load;
// false when there are none (or, for KeepRules::Reproducible, none whose
// load a second one would repeat), or a file they loaded changed (they are
// closed then, as they are when they cannot be put back).
bool take_kept(const std::string& key, std::size_t max_bytes, KeepRules mode) {
  if (!g_kept || g_kept->in_use || g_kept->key != key) return false;
  if (mode == KeepRules::Reproducible && !g_kept->reproducible) return false;
  const bool unchanged = std::all_of(g_kept->files.begin(), g_kept->files.end(), [max_bytes](const auto& file) {
    return content_sha256(file.first, max_bytes) == file.second;
  });
  bool restored = false;
  if (unchanged) {
    prolog::Frame frame;
    auto r = call_driver_keep("restore_mission", {new_atom(g_kept->module)});
    restored = r && r.value();
  }
  if (!restored) {
    close_kept();
    return false;
  }
  g_kept->in_use = true;
  return true;
}

// Keeps the rules just loaded into module when they can be put back
// (driver_keep.pl, keepable_mission/1) and, for KeepRules::Reproducible,
// when a second load would repeat their load (reproducible_mission/1), in
// place of any kept before.
bool keep(const std::string& key, const std::string& module, std::vector<PrologMessage> messages,
          const std::string& data_file, std::size_t max_bytes, KeepRules mode) {
  if (g_kept && g_kept->in_use) return false;  // another PrologMission has them
  prolog::Frame frame;
  term_t m = new_atom(module);
  term_t files = PL_new_term_ref();
  if (auto r = call_driver_keep("keepable_mission", {m}); !r || !r.value()) return false;
  auto reproducible = call_driver_keep("reproducible_mission", {m});
  const bool repeats = reproducible && reproducible.value();
  if (mode == KeepRules::Reproducible && !repeats) return false;
  if (auto r = call_driver_keep("mission_files", {m, files}); !r || !r.value()) return false;
  KeptRules kept{key, module, {}, std::move(messages), data_file, repeats, true};
  term_t head = PL_new_term_ref();
  term_t tail = PL_copy_term_ref(files);
  while (PL_get_list(tail, head, tail)) {
    std::string file = prolog::text_of(head);
    std::string sha256 = content_sha256(file, max_bytes);
    if (sha256.empty()) return false;
    kept.files.emplace_back(std::move(file), std::move(sha256));
  }
  if (kept.files.empty()) return false;
  if (auto r = call_driver_keep("keep_mission", {m}); !r || !r.value()) return false;
  if (g_kept) close_kept();
  g_kept = std::move(kept);
  return true;
}

}  // namespace

core::Result<std::unique_ptr<PrologMission>> PrologMission::load(const std::string& path,
                                                                 const tactical::Catalogue& catalogue,
                                                                 core::SourceManager& sources,
                                                                 core::DiagnosticSink& sink, const LoadLimits& limits,
                                                                 KeepRules keep, tactical::ExecutionLevel level) {
  std::vector<PrologMessage> messages;
  auto mission = load_collecting(path, catalogue, messages, limits, keep, level);
  report_messages(messages, limits.max_bytes, sources, sink);
  return mission;
}

core::Result<std::unique_ptr<PrologMission>> PrologMission::load_collecting(
    const std::string& path, const tactical::Catalogue& catalogue, std::vector<PrologMessage>& messages,
    const LoadLimits& limits, KeepRules keep_rules, tactical::ExecutionLevel level) {
  std::error_code ec;
  // A file named .pl must be one once opened (links resolved): a link
  // m.pl -> ~/.ssh/id_rsa had its lines shown in the syntax errors. The
  // files it consults are checked by the driver (mission_file/2).
  if (auto probe = core::read_regular_file_as_named(path, limits.max_bytes, ".pl"); !probe) {
    if (probe.error().code != core::ErrorCode::Overflow) return probe.error();
    messages.push_back(
        {core::DiagnosticKind::FileTooLarge, path, 0, 0,
         fmt::format("the file is over the limit of {} bytes for rules (--max-rules-size)", limits.max_bytes)});
    return core::make_error(core::ErrorCode::InvalidInput, fmt::format("{}: 1 error", path));
  }
  // The driver first: it refuses a thread other than SWI-Prolog's.
  if (auto r = prolog_detail::ensure_driver(); !r) return r.error();
  prolog_detail::set_max_rules_bytes(limits.max_bytes);
  std::unique_ptr<PrologMission> mission(new PrologMission());
  mission->path_ = path;
  mission->name_ = fs::path(path).stem().string();

  const std::string specs_text = primitive_specs(catalogue);
  fs::path absolute = fs::absolute(path, ec);
  const std::string key = keep_rules != KeepRules::No
                              ? kept_key(path, absolute.lexically_normal().string(), specs_text, limits, level)
                              : std::string();
  if (keep_rules != KeepRules::No && take_kept(key, limits.max_bytes, keep_rules)) {
    mission->module_ = g_kept->module;
    mission->data_file_ = g_kept->data_file;
    mission->kept_ = true;
    messages.insert(messages.end(), g_kept->messages.begin(), g_kept->messages.end());
    return mission;
  }
  // A file is loaded into one module at a time: kept rules that may share
  // files with these go first.
  if (g_kept && !g_kept->in_use) close_kept();
  const std::size_t first_message = messages.size();

  prolog::Frame frame;
  term_t module = PL_new_term_ref();
  auto specs = prolog::parse_term(specs_text);
  if (!specs) return specs.error();
  if (auto r = call_driver("open_mission", {module, specs.value()}); !r || !r.value()) {
    return core::make_error(core::ErrorCode::Internal,
                            "cannot make a module for the mission: " + (r ? std::string("failed") : r.error().message));
  }
  mission->module_ = prolog::text_of(module);

  term_t file = new_atom(absolute.lexically_normal().string());
  term_t budget = PL_new_term_ref();
  if (!PL_put_int64(budget, static_cast<int64_t>(limits.inferences))) PL_clear_exception();
  // One wall-clock limit for the load (directives included) and the check.
  // The driver loads the rules from a stream, outside the sig_atomic/1 in
  // which SWI-Prolog 9.0.4 loads a file by name, so the prolog::interrupt reaches a
  // directive (driver_load.pl, load_mission_file/3).
  TimeLimit time_limit(limits.time);
  // With the driver's exception hook: what must stop the load (the time
  // limit, the inference budget) cannot be caught by a directive.
  core::Result<bool> loaded = false;
  {
    prolog::Query q(driver_goal("load_mission", {new_atom(mission->module_), file, budget}), false,
                    /*exception_hook=*/true);
    switch (q.next()) {
      case prolog::Query::Status::True:
      case prolog::Query::Status::Last: loaded = true; break;
      case prolog::Query::Status::False: loaded = false; break;
      default: loaded = core::make_error(core::ErrorCode::InvalidInput, q.exception_text()); break;
    }
  }
  (void)prolog::call_once("strata_driver:unlimited");
  collect_load_messages(mission->module_, path, messages);
  // '$aborted': a stop while loading, already among the messages.
  if (!loaded && loaded.error().message != "'$aborted'") {  // text-ok: a Prolog exception term, not words
    messages.push_back({core::DiagnosticKind::PrologLoadError, path, 0, 0, loaded.error().message});
  }

  // Rules that did not load whole are not checked: what is missing would
  // only echo the load errors.
  const bool load_errors =
      !loaded || std::any_of(messages.begin(), messages.end(), [](const PrologMessage& m) { return is_error(m); });
  if (!load_errors) {
    check_rules(*mission, messages);
    // Literal numbers out of the catalogue's ranges, as CORAL's check finds
    // them: in the mission's own file (the files it loads are its library).
    if (auto text = core::read_regular_file(path, limits.max_bytes)) {
      for (auto& p : scan_primitive_arguments(text.value(), catalogue)) {
        messages.push_back({core::DiagnosticKind::ArgumentOutOfRange, path, static_cast<std::uint32_t>(p.line),
                            static_cast<std::uint32_t>(p.column), std::move(p.text)});
      }
    }
    check_level(*mission, catalogue, level, limits.max_bytes, messages);
  }
  if (time_limit.expired() &&
      std::none_of(messages.begin(), messages.end(), [](const PrologMessage& m) { return is_error(m); })) {
    messages.push_back({core::DiagnosticKind::PrologLoadError, path, 0, 0,
                        fmt::format("loading and checking took longer than their time limit ({} ms, --load-time-limit)",
                                    limits.time.count())});
  }
  term_t data = PL_new_term_ref();
  if (auto r = call_driver("mission_data", {new_atom(mission->module_), data}); r && r.value()) {
    fs::path written = prolog::text_of(data);
    mission->data_file_ =
        (written.is_absolute() ? written : fs::path(path).parent_path() / written).lexically_normal().string();
  }
  std::size_t errors = 0;
  for (const auto& m : messages) errors += is_error(m) ? 1 : 0;
  if (errors > 0) {
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("{}: {} error{}", path, errors, errors == 1 ? "" : "s"));
  }
  if (keep_rules != KeepRules::No) {
    mission->kept_ =
        keep(key, mission->module_, {messages.begin() + static_cast<std::ptrdiff_t>(first_message), messages.end()},
             mission->data_file_, limits.max_bytes, keep_rules);
  }
  return mission;
}

PrologMission::~PrologMission() {
  if (module_.empty()) return;
  if (kept_ && g_kept && g_kept->module == module_) {
    g_kept->in_use = false;  // put back when taken again
    return;
  }
  prolog::Frame frame;
  (void)call_driver("close_mission", {new_atom(module_)});
}

PrologMissionQuery::PrologMissionQuery(PrologMission& mission, PrologHost& host, std::uint64_t inference_limit)
    : mission_(mission), host_(host) {
  mission_.started_ = true;
  frame_ = PL_open_foreign_frame();
  term_t limit = PL_new_term_ref();
  if (!PL_put_int64(limit, static_cast<int64_t>(inference_limit))) PL_clear_exception();
  term_t goal = driver_goal("run_mission", {new_atom(mission_.module()), limit});
  query_ = std::make_unique<prolog::Query>(goal, /*allow_yield=*/true, /*exception_hook=*/true);
}

PrologMissionQuery::~PrologMissionQuery() { close(); }

prolog::Query::Status PrologMissionQuery::next() {
  if (!query_) return prolog::Query::Status::False;
  prolog_detail::set_running_host(&host_);
  prolog::Query::Status status;
  bool interrupted = false;
  {
    prolog::InterruptScope scope(&host_);
    status = query_->next();
    interrupted = scope.interrupted();
  }
  prolog_detail::set_running_host(nullptr);
  if (status != prolog::Query::Status::Exception) return status;
  exception_ = query_->exception_text();
  if (exception_ == "'$aborted'") {
    // The driver turned what must end the mission into '$aborted', so the
    // rules could not catch it; it kept the cause.
    close();
    prolog::Frame frame;
    term_t cause = PL_new_term_ref();
    if (auto r = call_driver("stop_cause", {cause}); r && r.value()) exception_ = prolog::term_text(cause);
  }
  exception_ = without_module(exception_, mission_.module());
  const std::string& e = exception_;
  if (e == "strata_halt") {
    halted_ = 0;
  } else if (e.starts_with("strata_halt(")) {
    halted_ = std::atoi(e.c_str() + 12);
  } else if (e == "inference_limit_exceeded") {
    limit_exceeded_ = true;
  } else if (e.starts_with("error(resource_error(")) {
    out_of_stack_ = true;
  } else if (e.find("'I_YIELD'") != std::string::npos) {
    cannot_suspend_ = true;
  } else if (e == "strata_interrupted" || (interrupted && e == "'$aborted'")) {
    interrupted_ = true;
  }
  return status;
}

void PrologMissionQuery::close() {
  if (!query_) return;
  query_.reset();  // cuts the query
  PL_discard_foreign_frame(frame_);
  (void)prolog::call_once("strata_driver:unlimited");
}

bool interrupt_rules(const PrologHost& host) { return prolog::interrupt(&host); }

core::Result<RulesOutcome> mission_outcome(const PrologMission& mission) {
  prolog::Frame frame;
  term_t outcome = PL_new_term_ref();
  auto r = call_driver("mission_outcome", {new_atom(mission.module()), outcome});
  if (!r) return r.error();
  return prolog::text_of(outcome) == "aborted" ? RulesOutcome::Aborted : RulesOutcome::Completed;
}

}  // namespace strata::strategic
