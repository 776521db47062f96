#include "coral/arguments.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "core/text.h"

namespace strata::coral {

std::optional<double> ast::number_value(const Literal& literal) {
  if (literal.kind != Literal::Kind::Integer && literal.kind != Literal::Kind::Float) return std::nullopt;
  const char* first = literal.value.data();
  const char* last = first + literal.value.size();
  double n = 0;
  auto [end, ec] = std::from_chars(first, last, n);
  if (ec != std::errc() || end != last || !std::isfinite(n)) return std::nullopt;
  return n;
}

namespace {

using core::DiagnosticKind;

std::string_view type_name(ast::ParamType type) { return type == ast::ParamType::Number ? "number" : "string"; }

std::string with_unit(double n, const std::string& unit) {
  return unit.empty() ? fmt::format("{}", n) : fmt::format("{} {}", n, unit);
}

std::vector<const ast::Phase*> phase_calls(const ast::Net& net) {
  std::vector<const ast::Phase*> out;
  for (const auto& t : net.transitions) {
    for (const auto& action : t.actions) {
      if (const auto* phase = std::get_if<ast::Phase>(&action)) out.push_back(phase);
    }
  }
  return out;
}

}  // namespace

ArgumentChecker::ArgumentChecker(const NetLibrary& library, core::DiagnosticSink& sink, const CheckOptions& options)
    : library_(library), sink_(sink), options_(options) {
  compute_ranges();
}

std::optional<std::size_t> ArgumentChecker::param_index(const ast::Net& net, std::string_view name) const {
  for (std::size_t i = 0; i < net.params.size(); ++i) {
    if (net.params[i].name.text == name) return i;
  }
  return std::nullopt;
}

const ast::Net* ArgumentChecker::callee_of(const ast::Phase& call) const {
  auto it = library_.find(call.phase.text);
  if (it == library_.end() || it->second->kind == ast::Net::Kind::Mission) return nullptr;
  return it->second;
}

void ArgumentChecker::narrow(const ast::Net& net, std::vector<Range>& ranges, const std::vector<ast::Literal>& args,
                             const std::vector<Range>& wanted) {
  for (std::size_t i = 0; i < args.size() && i < wanted.size(); ++i) {
    if (args[i].kind != ast::Literal::Kind::Parameter) continue;
    auto j = param_index(net, args[i].text);
    if (!j) continue;
    Range& r = ranges[*j];
    const Range& w = wanted[i];
    if (w.lo && (!r.lo || w.lo->value > r.lo->value)) r.lo = w.lo;
    if (w.hi && (!r.hi || w.hi->value < r.hi->value)) r.hi = w.hi;
  }
}

// Callees first (an iterative depth-first search, so a long chain of phases
// cannot overflow the stack); a callee still on the stack closes a cycle and
// adds nothing.
void ArgumentChecker::compute_ranges() {
  std::vector<const ast::Net*> roots;
  roots.reserve(library_.size());
  for (const auto& [name, net] : library_) roots.push_back(net);
  std::sort(roots.begin(), roots.end(),
            [](const ast::Net* a, const ast::Net* b) { return a->name.text < b->name.text; });
  enum class Mark { None, Active, Done };
  std::unordered_map<const ast::Net*, Mark> marks;
  struct Frame {
    const ast::Net* net;
    std::vector<const ast::Phase*> calls;
    std::size_t next = 0;
  };
  auto local = [&](const ast::Net& net) {
    std::vector<Range> ranges(net.params.size());
    for (const auto& t : net.transitions) {
      for (const auto& action : t.actions) {
        if (const auto* phase = std::get_if<ast::Phase>(&action)) {
          const ast::Net* callee = callee_of(*phase);
          auto it = callee ? ranges_.find(callee) : ranges_.end();
          if (it != ranges_.end()) narrow(net, ranges, phase->args, it->second);
          continue;
        }
        const auto& tactic = std::get<ast::Tactic>(action);
        if (!tactic.function || !options_.primitive) continue;
        const ast::Call& call = *tactic.function;
        if (std::none_of(call.args.begin(), call.args.end(),
                         [](const ast::Literal& a) { return a.kind == ast::Literal::Kind::Parameter; })) {
          continue;
        }
        auto sig = options_.primitive(call.name.text);
        if (!sig) continue;
        std::vector<Range> wanted;
        for (std::size_t i = 0; i < sig->args.size() && i < call.args.size(); ++i) {
          const ArgumentSignature& s = sig->args[i];
          std::string what = fmt::format("'{}' argument '{}'", call.name.text, s.name);
          Range r;
          if (s.min) r.lo = Bound{*s.min, s.unit, what, call.args[i].span};
          if (s.max) r.hi = Bound{*s.max, s.unit, what, call.args[i].span};
          wanted.push_back(std::move(r));
        }
        narrow(net, ranges, call.args, wanted);
      }
    }
    return ranges;
  };
  for (const ast::Net* root : roots) {
    if (marks[root] != Mark::None) continue;
    std::vector<Frame> stack;
    marks[root] = Mark::Active;
    stack.push_back({root, phase_calls(*root)});
    while (!stack.empty()) {
      Frame& f = stack.back();
      if (f.next == f.calls.size()) {
        if (!f.net->params.empty()) ranges_[f.net] = local(*f.net);
        marks[f.net] = Mark::Done;
        stack.pop_back();
        continue;
      }
      const ast::Net* callee = callee_of(*f.calls[f.next++]);
      if (!callee || marks[callee] != Mark::None) continue;
      marks[callee] = Mark::Active;
      stack.push_back({callee, phase_calls(*callee)});
    }
  }
}

void ArgumentChecker::check_params(const ast::Net& net) {
  std::unordered_map<std::string_view, const ast::Param*> seen;
  for (const auto& p : net.params) {
    auto [it, fresh] = seen.emplace(p.name.text, &p);
    if (!fresh) {
      auto* d = sink_.report(DiagnosticKind::DuplicateParameter, p.name.span,
                             fmt::format("parameter '{}' is declared twice in '{}'", p.name.text, net.name.text));
      core::add_note(d, it->second->name.span, "first declared here");
    }
  }
}

void ArgumentChecker::check_names(const ast::Net& net, const std::vector<ast::Literal>& args) {
  for (const auto& a : args) {
    if (a.kind != ast::Literal::Kind::Parameter || param_index(net, a.text)) continue;
    core::Diagnostic* d = nullptr;
    if (net.params.empty()) {
      d = sink_.report(DiagnosticKind::UnknownParameter, a.span,
                       fmt::format("'{}' is not a literal, and {} '{}' has no parameters", a.text,
                                   net.kind == ast::Net::Kind::Mission ? "mission" : "net", net.name.text));
    } else {
      d = sink_.report(DiagnosticKind::UnknownParameter, a.span,
                       fmt::format("'{}' is not a parameter of '{}'", a.text, net.name.text));
      std::vector<std::string> names;
      for (const auto& p : net.params) names.push_back(p.name.text);
      if (auto s = core::suggest(a.text, names)) core::add_note(d, fmt::format("did you mean '{}'?", *s));
    }
    core::add_note(d, "a string argument is written in quotes, a number as digits");
  }
}

void ArgumentChecker::check_report_param(const ast::Net& net, const ast::Literal& name) {
  auto j = param_index(net, name.text);
  if (!j) {
    auto* d = sink_.report(DiagnosticKind::TacticArguments, name.span,
                           fmt::format("TACTIC(REPORT, ...) takes a string in quotes, or a string parameter of its "
                                       "net; '{}' is no parameter of '{}'",
                                       name.text, net.name.text));
    std::vector<std::string> names;
    for (const auto& p : net.params) {
      if (p.type == ast::ParamType::String) names.push_back(p.name.text);
    }
    if (auto s = core::suggest(name.text, names)) core::add_note(d, fmt::format("did you mean '{}'?", *s));
    return;
  }
  const ast::Param& p = net.params[*j];
  if (p.type != ast::ParamType::String) {
    auto* d = sink_.report(
        DiagnosticKind::ArgumentType, name.span,
        fmt::format("REPORT's text is a string, but '{}' is a {} parameter", name.text, type_name(p.type)));
    core::add_note(d, p.span, "declared here (declare it `string " + p.name.text + "` to report it)");
  }
}

namespace {

// One literal number against a range: ArgumentOutOfRange at the literal,
// with a note at the use that sets the bound when it is elsewhere.
void check_number(core::DiagnosticSink& sink, const ast::Literal& a, const std::string& subject,
                  const std::optional<double>& lo, const std::optional<double>& hi, const std::string& unit,
                  const std::string& what, const core::SourceSpan* use_lo, const core::SourceSpan* use_hi) {
  auto v = ast::number_value(a);
  if (!v) {
    sink.report(DiagnosticKind::ArgumentOutOfRange, a.span,
                fmt::format("{} is {}, which is not a finite number", subject, a.text));
    return;
  }
  const bool below = lo && *v < *lo;
  const bool above = hi && *v > *hi;
  if (!below && !above) return;
  std::string bound = below ? fmt::format("below the minimum {}", with_unit(*lo, unit))
                            : fmt::format("above the maximum {}", with_unit(*hi, unit));
  if (!what.empty()) bound += " of " + what;
  auto* d =
      sink.report(DiagnosticKind::ArgumentOutOfRange, a.span, fmt::format("{} is {}, {}", subject, a.text, bound));
  const core::SourceSpan* use = below ? use_lo : use_hi;
  if (use) core::add_note(d, *use, fmt::format("it is passed to {} here", what));
}

}  // namespace

void ArgumentChecker::check_primitive_args(const ast::Net& net, const ast::Call& call, const PrimitiveSignature& sig) {
  for (std::size_t i = 0; i < call.args.size() && i < sig.args.size(); ++i) {
    const ast::Literal& a = call.args[i];
    const ArgumentSignature& s = sig.args[i];
    const std::string subject = fmt::format("'{}' argument '{}'", call.name.text, s.name);
    const std::string_view wanted = s.is_number ? "number" : "string";
    if (a.kind == ast::Literal::Kind::Parameter) {
      auto j = param_index(net, a.text);
      if (!j) continue;  // check_names reports it
      const ast::Param& p = net.params[*j];
      if ((p.type == ast::ParamType::Number) != s.is_number) {
        auto* d = sink_.report(
            DiagnosticKind::ArgumentType, a.span,
            fmt::format("{} is a {}, but '{}' is a {} parameter", subject, wanted, a.text, type_name(p.type)));
        core::add_note(d, p.span, "declared here");
      }
    } else if (a.kind == ast::Literal::Kind::String) {
      if (s.is_number) {
        sink_.report(DiagnosticKind::ArgumentType, a.span,
                     fmt::format("{} is a number{}, not a string", subject, s.unit.empty() ? "" : " in " + s.unit));
      }
    } else if (!s.is_number) {
      sink_.report(DiagnosticKind::ArgumentType, a.span,
                   fmt::format("{} is a string, not a number: write it in quotes", subject));
    } else {
      check_number(sink_, a, subject, s.min, s.max, s.unit, "", nullptr, nullptr);
    }
  }
}

void ArgumentChecker::check_phase_args(const ast::Net& caller, const ast::Phase& call, const ast::Net& callee) {
  if (call.args.size() != callee.params.size()) {
    std::string params;
    for (const auto& p : callee.params) params += (params.empty() ? "" : ", ") + p.name.text;
    auto* d = sink_.report(DiagnosticKind::PhaseArguments, call.phase.span,
                           fmt::format("phase '{}' takes {} argument{}, but {} given", call.phase.text,
                                       callee.params.size(), callee.params.size() == 1 ? "" : "s", call.args.size()));
    core::add_note(d, callee.span,
                   params.empty() ? std::string("it declares no parameters")
                                  : fmt::format("its parameters, in order: {}", params));
    return;
  }
  auto found = ranges_.find(&callee);
  for (std::size_t i = 0; i < call.args.size(); ++i) {
    const ast::Literal& a = call.args[i];
    const ast::Param& p = callee.params[i];
    const std::string subject = fmt::format("phase '{}' parameter '{}'", callee.name.text, p.name.text);
    if (a.kind == ast::Literal::Kind::Parameter) {
      auto j = param_index(caller, a.text);
      if (!j) continue;  // check_names reports it
      const ast::Param& mine = caller.params[*j];
      if (mine.type != p.type) {
        auto* d = sink_.report(DiagnosticKind::ArgumentType, a.span,
                               fmt::format("{} is a {}, but '{}' is a {} parameter", subject, type_name(p.type), a.text,
                                           type_name(mine.type)));
        core::add_note(d, p.span, "declared here");
      }
    } else if ((a.kind == ast::Literal::Kind::String) != (p.type == ast::ParamType::String)) {
      auto* d = sink_.report(DiagnosticKind::ArgumentType, a.span,
                             fmt::format("{} is a {}, not a {}", subject, type_name(p.type),
                                         a.kind == ast::Literal::Kind::String ? "string" : "number"));
      core::add_note(d, p.span, "declared here");
    } else if (p.type == ast::ParamType::Number) {
      const Range none;
      const Range& r = found != ranges_.end() ? found->second[i] : none;
      const Bound* b = r.lo ? &*r.lo : r.hi ? &*r.hi : nullptr;
      // The two bounds may come from different uses; each message names its own.
      auto v = ast::number_value(a);
      const Bound* hit = !v ? b : (r.lo && *v < r.lo->value) ? &*r.lo : (r.hi && *v > r.hi->value) ? &*r.hi : b;
      check_number(sink_, a, subject, r.lo ? std::optional(r.lo->value) : std::nullopt,
                   r.hi ? std::optional(r.hi->value) : std::nullopt, hit ? hit->unit : "", hit ? hit->what : "",
                   r.lo ? &r.lo->use : nullptr, r.hi ? &r.hi->use : nullptr);
    }
  }
}

}  // namespace strata::coral
