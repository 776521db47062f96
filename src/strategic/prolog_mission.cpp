#include "strategic/prolog_mission.h"

#include <algorithm>
#include <cctype>
#include <iterator>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "core/file.h"
#include "strategic/prolog_driver_check_text.h"
#include "strategic/prolog_driver_text.h"
#include "strategic/prolog_rules_scan.h"
#include "prolog/interrupt.h"

namespace strata::prolog {
namespace {

namespace fs = std::filesystem;

// The executor whose query is running; set by MissionQuery::next().
Host* g_host = nullptr;
// LoadLimits::max_bytes of the load under way, for '$strata_scan'/2.
std::size_t g_max_rules_bytes = LoadLimits{}.max_bytes;

term_t new_atom(const std::string& name) {
  term_t t = PL_new_term_ref();
  PL_put_atom_chars(t, name.c_str());
  return t;
}

// strata_driver:Name(Args...)
term_t driver_goal(const char* name, std::initializer_list<term_t> args) {
  term_t refs = PL_new_term_refs(static_cast<int>(args.size()));
  int i = 0;
  for (term_t a : args) {
    if (!PL_put_term(refs + i++, a)) PL_clear_exception();
  }
  term_t goal = PL_new_term_ref();
  term_t call = PL_new_term_ref();
  if (!PL_cons_functor_v(goal, PL_new_functor(PL_new_atom(name), args.size()), refs) ||
      !PL_cons_functor(call, PL_new_functor(PL_new_atom(":"), 2), new_atom("strata_driver"), goal)) {
    PL_clear_exception();
  }
  return call;
}

core::Result<bool> call_driver(const char* name, std::initializer_list<term_t> args) {
  return call_term(driver_goal(name, args));
}

// A primitive argument: a number, or text (an atom or a string). Raises a
// Prolog error and returns nullopt otherwise.
std::optional<tactical::Value> value_of(term_t t) {
  double number = 0;
  if (PL_is_number(t) && PL_get_float(t, &number)) return tactical::Value::of(number);
  char* s = nullptr;
  std::size_t len = 0;
  if (PL_get_nchars(t, &len, &s, CVT_ATOM | CVT_STRING | BUF_STACK | REP_UTF8)) {
    return tactical::Value::of(std::string(s, len));
  }
  if (PL_is_variable(t)) {
    PL_instantiation_error(t);
  } else {
    PL_type_error("number_or_text", t);
  }
  return std::nullopt;
}

bool call_arguments(term_t name_t, term_t list, std::string& name, std::vector<tactical::Value>& args) {
  char* s = nullptr;
  if (!PL_get_atom_chars(name_t, &s)) return PL_type_error("atom", name_t);
  name = s;
  term_t head = PL_new_term_ref();
  term_t tail = PL_copy_term_ref(list);
  while (PL_get_list(tail, head, tail)) {
    auto v = value_of(head);
    if (!v) return false;
    args.push_back(std::move(*v));
  }
  if (!PL_get_nil(tail)) return PL_type_error("list", list);
  return true;
}

bool no_host() {
  term_t ex = PL_new_term_ref();
  return PL_unify_term(ex, PL_FUNCTOR_CHARS, "strata_error", 1, PL_CHARS,
                       "a primitive was called outside a running mission") &&
         PL_raise_exception(ex);
}

// '$strata_call'(+Name, +Args, -Answer): yields to the host until the
// vehicle answers, then unifies Answer with 1 or 0.
foreign_t pl_strata_call(term_t name_t, term_t args_t, term_t answer_t, control_t handle) {
  alignas(8) static int token = 0;
  switch (PL_foreign_control(handle)) {
    case PL_FIRST_CALL: {
      if (!g_host) return no_host();
      std::string name;
      std::vector<tactical::Value> args;
      if (!call_arguments(name_t, args_t, name, args)) return FALSE;
      g_host->primitive(name, std::move(args));
      PL_yield_address(&token);
    }
    case PL_RESUME: {
      auto answer = g_host ? g_host->answer() : std::nullopt;
      if (!answer) {
        term_t ex = PL_new_term_ref();
        PL_put_atom_chars(ex, "strata_cancelled");
        return PL_raise_exception(ex);
      }
      return PL_unify_integer(answer_t, *answer);
    }
    default: return TRUE;
  }
}

foreign_t pl_strata_report(term_t name_t, term_t args_t) {
  if (!g_host) return no_host();
  std::string name;
  std::vector<tactical::Value> args;
  if (!call_arguments(name_t, args_t, name, args)) return FALSE;
  g_host->report(name, std::move(args));
  return TRUE;
}

// '$strata_phase'(+Event, +Phase): Event is start or end(Exit).
foreign_t pl_strata_phase(term_t event_t, term_t phase_t) {
  if (!g_host) return TRUE;  // the rules run outside a mission (plunit)
  std::string phase = text_of(phase_t);
  char* s = nullptr;
  if (PL_get_atom_chars(event_t, &s)) {
    g_host->phase_started(phase);
    return TRUE;
  }
  term_t exit = PL_new_term_ref();
  if (PL_is_functor(event_t, PL_new_functor(PL_new_atom("end"), 1)) && PL_get_arg(1, event_t, exit)) {
    g_host->phase_ended(phase, text_of(exit));
    return TRUE;
  }
  return PL_domain_error("phase_event", event_t);
}

// '$strata_scan'(+File, -Problem): Problem is ok, or problem(Line, Column,
// Text) for what the reader must not see (scan_rules_text()). A file that
// cannot be read is ok here: loading it says so.
foreign_t pl_strata_scan(term_t file_t, term_t problem_t) {
  char* file = nullptr;
  if (!PL_get_file_name(file_t, &file, 0)) return FALSE;
  auto read = core::read_regular_file(file, g_max_rules_bytes);
  if (!read && read.error().code == core::ErrorCode::Overflow) {
    return PL_unify_term(problem_t, PL_FUNCTOR_CHARS, "problem", 3, PL_INT64, int64_t{0}, PL_INT64, int64_t{0},
                         PL_UTF8_STRING,
                         fmt::format("the file is over the limit of {} bytes for rules (--max-rules-size)",
                                     g_max_rules_bytes)
                             .c_str());
  }
  if (!read && read.error().message.ends_with("not a regular file")) {
    return PL_unify_term(problem_t, PL_FUNCTOR_CHARS, "problem", 3, PL_INT64, int64_t{0}, PL_INT64, int64_t{0},
                         PL_UTF8_STRING, "not a regular file (a FIFO or a device is never read)");
  }
  if (!read) return PL_unify_atom_chars(problem_t, "ok");
  const auto found = scan_rules_text(read.value());
  if (!found) return PL_unify_atom_chars(problem_t, "ok");
  return PL_unify_term(problem_t, PL_FUNCTOR_CHARS, "problem", 3, PL_INT64, static_cast<int64_t>(found->line),
                       PL_INT64, static_cast<int64_t>(found->column), PL_UTF8_STRING, found->text.c_str());
}

// Loads one of the driver's modules from its text.
core::Result<void> load_module_text(const char* module, std::string_view text) {
  Frame frame;
  auto goal = parse_term(
      "open_string(Text, S), call_cleanup(load_files(Module, [stream(S), silent(true), imports([])]), close(S))");
  if (!goal) return goal.error();
  term_t open = PL_new_term_ref();
  term_t text_t = PL_new_term_ref();
  term_t load = PL_new_term_ref();
  term_t call_load = PL_new_term_ref();
  term_t module_t = PL_new_term_ref();
  if (!PL_get_arg(1, goal.value(), open) || !PL_get_arg(1, open, text_t) ||
      !PL_unify_chars(text_t, PL_STRING, text.size(), text.data()) || !PL_get_arg(2, goal.value(), load) ||
      !PL_get_arg(1, load, call_load) || !PL_get_arg(1, call_load, module_t) ||
      !PL_unify_atom_chars(module_t, module)) {
    return core::make_error(core::ErrorCode::Internal, "cannot build the driver's load goal");
  }
  auto r = call_term(goal.value());
  if (!r || !r.value()) {
    return core::make_error(core::ErrorCode::Internal,
                            fmt::format("the PROLOG driver ({}) did not load: {}", module,
                                        r ? std::string("failed") : r.error().message));
  }
  return {};
}

core::Result<void> ensure_driver() {
  static bool loaded = false;
  if (loaded) return {};
  if (auto r = initialise(); !r) return r.error();
  if (auto r = load_module_text("strata_driver_check", kDriverCheckText); !r) return r;
  if (auto r = load_module_text("strata_driver", kDriverText); !r) return r;
  PL_register_foreign_in_module("strata_driver", "$strata_call", 3,
                                reinterpret_cast<pl_function_t>(pl_strata_call), PL_FA_NONDETERMINISTIC);
  PL_register_foreign_in_module("strata_driver", "$strata_report", 2,
                                reinterpret_cast<pl_function_t>(pl_strata_report), 0);
  PL_register_foreign_in_module("strata_driver", "$strata_scan", 2,
                                reinterpret_cast<pl_function_t>(pl_strata_scan), 0);
  PL_register_foreign_in_module("strata_driver", "$strata_phase", 2,
                                reinterpret_cast<pl_function_t>(pl_strata_phase), 0);
  if (auto set = call_once("assertz(strata_driver:uncatchable_stops)"); !set || !set.value()) {
    return core::make_error(core::ErrorCode::Internal, "cannot set up the PROLOG driver");
  }
  loaded = true;
  return {};
}

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
    out += fmt::format("primitive({},{},{},{})", prolog_atom(p.name), tactical::kind_name(p.kind),
                       p.min_args(), p.max_args());
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

void collect_load_messages(const std::string& module, const std::string& root, std::vector<Message>& out) {
  Frame frame;
  term_t a = PL_new_term_refs(5);
  term_t goal = driver_goal("load_message", {a, a + 1, a + 2, a + 3, a + 4});
  Query q(goal, false);
  while (true) {
    auto s = q.next();
    if (s != Query::Status::True && s != Query::Status::Last) break;
    Message m;
    m.error = text_of(a) == "error";
    m.file = shown_path(text_of(a + 1));
    if (m.file.empty()) m.file = root;  // SWI gave no place: the mission's file
    m.line = get_uint(a + 2);
    m.column = get_uint(a + 3);
    m.text = without_module(text_of(a + 4), module);
    out.push_back(std::move(m));
    if (s == Query::Status::Last) break;
  }
}

// The driver's check: undefined calls (unknown primitives among them) and a
// missing mission/0.
void check_rules(const Mission& mission, std::vector<Message>& messages) {
  term_t problems = PL_new_term_ref();
  auto checked = call_driver("check_mission", {new_atom(mission.module()), problems});
  if (!checked || !checked.value()) {
    messages.push_back({true, mission.path(), 0, 0,
                        "the rules could not be checked: " + (checked ? std::string("failed") : checked.error().message)});
  } else {
    term_t head = PL_new_term_ref();
    term_t arg = PL_new_term_ref();
    term_t tail = PL_copy_term_ref(problems);
    while (PL_get_list(tail, head, tail)) {
      Message m;
      PL_get_arg(1, head, arg);
      m.file = shown_path(text_of(arg));
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
      m.text = text_of(arg);
      messages.push_back(std::move(m));
    }
  }
}

// A wall-clock limit on the Prolog that runs on this thread while it lives:
// past it, a watchdog thread interrupts it (prolog/interrupt.h: also out of
// sleep/1), again every 50 ms, since a directive's catch/3 could swallow one
// raise when the query runs without the driver's exception hook.
class TimeLimit {
 public:
  explicit TimeLimit(std::chrono::milliseconds limit) : scope_(this) {
    watchdog_ = std::thread([this, limit] {
      std::unique_lock lock(mutex_);
      if (done_cv_.wait_for(lock, limit, [this] { return done_; })) return;
      expired_ = true;
      while (!done_) {
        interrupt(this);
        done_cv_.wait_for(lock, std::chrono::milliseconds(50), [this] { return done_; });
      }
    });
  }
  ~TimeLimit() {
    {
      std::lock_guard lock(mutex_);
      done_ = true;
    }
    done_cv_.notify_all();
    watchdog_.join();
  }
  TimeLimit(const TimeLimit&) = delete;
  TimeLimit& operator=(const TimeLimit&) = delete;

  bool expired() {
    std::lock_guard lock(mutex_);
    return expired_;
  }

 private:
  InterruptScope scope_;
  std::mutex mutex_;
  std::condition_variable done_cv_;
  bool done_ = false;
  bool expired_ = false;
  std::thread watchdog_;
};

}  // namespace

std::string format_message(const Message& m) {
  std::string where = m.file;
  if (!where.empty() && m.line > 0) where += fmt::format(":{}", m.line);
  if (!where.empty() && m.line > 0 && m.column > 0) where += fmt::format(":{}", m.column);
  return fmt::format("{}{}{}: {}", where, where.empty() ? "" : ": ", m.error ? "error" : "warning", m.text);
}

core::Result<std::unique_ptr<Mission>> Mission::load(const std::string& path,
                                                     const tactical::Catalogue& catalogue,
                                                     std::vector<Message>& messages,
                                                     const LoadLimits& limits) {
  std::error_code ec;
  if (auto probe = core::read_regular_file(path, limits.max_bytes); !probe) {
    if (probe.error().code != core::ErrorCode::Overflow) return probe.error();
    messages.push_back({true, path, 0, 0,
                        fmt::format("the file is over the limit of {} bytes for rules (--max-rules-size)",
                                    limits.max_bytes)});
    return core::make_error(core::ErrorCode::InvalidInput, fmt::format("{}: 1 error", path));
  }
  g_max_rules_bytes = limits.max_bytes;
  if (auto r = ensure_driver(); !r) return r.error();
  std::unique_ptr<Mission> mission(new Mission());
  mission->path_ = path;
  mission->name_ = fs::path(path).stem().string();

  Frame frame;
  term_t module = PL_new_term_ref();
  auto specs = parse_term(primitive_specs(catalogue));
  if (!specs) return specs.error();
  if (auto r = call_driver("open_mission", {module, specs.value()}); !r || !r.value()) {
    return core::make_error(core::ErrorCode::Internal, "cannot make a module for the mission: " +
                                                           (r ? std::string("failed") : r.error().message));
  }
  mission->module_ = text_of(module);

  fs::path absolute = fs::absolute(path, ec);
  term_t file = new_atom(absolute.lexically_normal().string());
  term_t budget = PL_new_term_ref();
  if (!PL_put_int64(budget, static_cast<int64_t>(limits.inferences))) PL_clear_exception();
  // One wall-clock limit for the load (directives included) and the check.
  // The driver loads the rules from a stream, outside the sig_atomic/1 in
  // which SWI-Prolog 9.0.4 loads a file by name, so the interrupt reaches a
  // directive (driver.pl, load_mission_file/3).
  TimeLimit time_limit(limits.time);
  // With the driver's exception hook: what must stop the load (the time
  // limit, the inference budget) cannot be caught by a directive.
  core::Result<bool> loaded = false;
  {
    Query q(driver_goal("load_mission", {new_atom(mission->module_), file, budget}), false,
            /*exception_hook=*/true);
    switch (q.next()) {
      case Query::Status::True:
      case Query::Status::Last: loaded = true; break;
      case Query::Status::False: loaded = false; break;
      default: loaded = core::make_error(core::ErrorCode::InvalidInput, q.exception_text()); break;
    }
  }
  (void)call_once("strata_driver:unlimited");
  collect_load_messages(mission->module_, path, messages);
  // '$aborted': a stop while loading, already among the messages.
  if (!loaded && loaded.error().message != "'$aborted'") {
    messages.push_back({true, path, 0, 0, loaded.error().message});
  }

  // Rules that did not load whole are not checked: what is missing would
  // only echo the load errors.
  const bool load_errors =
      !loaded || std::any_of(messages.begin(), messages.end(), [](const Message& m) { return m.error; });
  if (!load_errors) check_rules(*mission, messages);
  if (time_limit.expired() &&
      std::none_of(messages.begin(), messages.end(), [](const Message& m) { return m.error; })) {
    messages.push_back({true, path, 0, 0,
                        fmt::format("loading and checking took longer than their time limit ({} ms, --load-time-limit)",
                                    limits.time.count())});
  }
  term_t data = PL_new_term_ref();
  if (auto r = call_driver("mission_data", {new_atom(mission->module_), data}); r && r.value()) {
    fs::path written = text_of(data);
    mission->data_file_ =
        (written.is_absolute() ? written : fs::path(path).parent_path() / written).lexically_normal().string();
  }
  std::size_t errors = 0;
  for (const auto& m : messages) errors += m.error ? 1 : 0;
  if (errors > 0) {
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("{}: {} error{}", path, errors, errors == 1 ? "" : "s"));
  }
  return mission;
}

Mission::~Mission() {
  if (module_.empty()) return;
  Frame frame;
  (void)call_driver("close_mission", {new_atom(module_)});
}

MissionQuery::MissionQuery(Mission& mission, Host& host, std::uint64_t inference_limit)
    : mission_(mission), host_(host) {
  mission_.started_ = true;
  frame_ = PL_open_foreign_frame();
  term_t limit = PL_new_term_ref();
  if (!PL_put_int64(limit, static_cast<int64_t>(inference_limit))) PL_clear_exception();
  term_t goal = driver_goal("run_mission", {new_atom(mission_.module()), limit});
  query_ = std::make_unique<Query>(goal, /*allow_yield=*/true, /*exception_hook=*/true);
}

MissionQuery::~MissionQuery() { close(); }

Query::Status MissionQuery::next() {
  if (!query_) return Query::Status::False;
  g_host = &host_;
  Query::Status status;
  bool interrupted = false;
  {
    InterruptScope scope(&host_);
    status = query_->next();
    interrupted = scope.interrupted();
  }
  g_host = nullptr;
  if (status != Query::Status::Exception) return status;
  exception_ = query_->exception_text();
  if (exception_ == "'$aborted'") {
    // The driver turned what must end the mission into '$aborted', so the
    // rules could not catch it; it kept the cause.
    close();
    Frame frame;
    term_t cause = PL_new_term_ref();
    if (auto r = call_driver("stop_cause", {cause}); r && r.value()) exception_ = term_text(cause);
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

void MissionQuery::close() {
  if (!query_) return;
  query_.reset();  // cuts the query
  PL_discard_foreign_frame(frame_);
  (void)call_once("strata_driver:unlimited");
}

bool interrupt_rules(const Host& host) { return interrupt(&host); }

core::Result<RulesOutcome> mission_outcome(const Mission& mission) {
  Frame frame;
  term_t outcome = PL_new_term_ref();
  auto r = call_driver("mission_outcome", {new_atom(mission.module()), outcome});
  if (!r) return r.error();
  return text_of(outcome) == "aborted" ? RulesOutcome::Aborted : RulesOutcome::Completed;
}

}  // namespace strata::prolog
