#include "coral/edit.h"

#include <algorithm>

#include <fmt/format.h>

#include "coral/lexer.h"
#include "coral/parser.h"

namespace strata::coral {
namespace {

using Op = Edit::Op;

core::Error invalid(std::string message) { return {core::ErrorCode::InvalidInput, std::move(message)}; }

struct Splice {
  std::uint32_t offset = 0;
  std::uint32_t length = 0;
  std::string text;
};

// A plain identifier, not a keyword.
bool is_name(std::string_view s) {
  core::DiagnosticSink sink;
  Lexer lexer(0, s, sink);
  Token t = lexer.next();
  return t.kind == TokenKind::Identifier && t.text == s && lexer.next().kind == TokenKind::EndOfFile &&
         sink.error_count() == 0;
}

class Editor {
 public:
  Editor(std::string_view text, const Edit& edit) : text_(text), e_(edit) {
    id_ = sources_.add("edit.coral", std::string(text));
    file_ = parse(sources_, id_, sink_);
  }

  core::Result<std::string> run() {
    for (const auto& n : file_.nets) net_ = n.name.text == e_.net ? &n : net_;
    if (!net_) return invalid(fmt::format("no net '{}' in the text", e_.net));
    if (auto r = dispatch(); !r) return r.error();
    std::sort(splices_.begin(), splices_.end(), [](const Splice& a, const Splice& b) { return a.offset > b.offset; });
    std::string out(text_);
    for (const auto& s : splices_) out.replace(s.offset, s.length, s.text);
    return out;
  }

 private:
  core::Result<void> dispatch() {
    switch (e_.op) {
      case Op::AddPlace: return add_place();
      case Op::DeletePlace: return delete_place();
      case Op::RenamePlace: return rename_place();
      case Op::SetInitial: return set_initial();
      case Op::AddTransition: return add_transition();
      case Op::DeleteTransition: return delete_transition();
      case Op::RenameTransition: return rename_transition();
      case Op::AddArc:
      case Op::DeleteArc:
      case Op::SetWeight: return arc();
      case Op::SetActions: return set_actions();
    }
    return invalid("unknown edit");
  }

  // ---- lookups --------------------------------------------------------------
  const ast::PlaceDecl* place(std::string_view name) const {
    for (const auto& p : net_->places) {
      if (p.name.text == name) return &p;
    }
    return nullptr;
  }
  const ast::Transition* transition(std::string_view name) const {
    for (const auto& t : net_->transitions) {
      if (t.name.text == name) return &t;
    }
    return nullptr;
  }
  core::Result<void> fresh_name(const std::string& name) const {
    if (!is_name(name))
      return invalid(fmt::format("'{}' is not a name (letters, digits and '_', not a keyword)", name));
    if (place(name) || transition(name)) return invalid(fmt::format("'{}' is already used in net '{}'", name, e_.net));
    return {};
  }

  // ---- text positions ---------------------------------------------------------
  std::uint32_t line_start(std::uint32_t offset) const {
    while (offset > 0 && text_[offset - 1] != '\n') --offset;
    return offset;
  }
  // offset, or the end of its line when nothing but blanks and a `//`
  // comment follow it there: what is added after a statement goes after
  // the comment that ends its line, not between them.
  std::uint32_t past_line_comment(std::uint32_t offset) const {
    std::uint32_t i = offset;
    while (i < text_.size() && (text_[i] == ' ' || text_[i] == '\t')) ++i;
    if (i + 1 >= text_.size() || text_[i] != '/' || text_[i + 1] != '/') return offset;
    while (i < text_.size() && text_[i] != '\n') ++i;
    return i;
  }
  std::string indent_of(std::uint32_t offset) const {
    const std::uint32_t start = line_start(offset);
    std::uint32_t end = start;
    while (end < offset && (text_[end] == ' ' || text_[end] == '\t')) ++end;
    return std::string(text_.substr(start, end - start));
  }
  // Removes [offset, offset + length) and, when nothing else is on its
  // lines, the lines themselves.
  void remove_lines(std::uint32_t offset, std::uint32_t length) {
    std::uint32_t begin = offset, end = offset + length;
    const std::uint32_t ls = line_start(begin);
    bool blank_before = text_.substr(ls, begin - ls).find_first_not_of(" \t") == std::string_view::npos;
    std::uint32_t le = end;
    while (le < text_.size() && (text_[le] == ' ' || text_[le] == '\t')) ++le;
    const bool blank_after = le >= text_.size() || text_[le] == '\n';
    if (blank_before && blank_after) {
      begin = ls;
      end = le < text_.size() ? le + 1 : le;
    }
    splices_.push_back({begin, end - begin, ""});
  }
  std::string_view slice(const core::SourceSpan& s) const { return text_.substr(s.offset, s.length); }
  std::string body_indent() const {
    if (!net_->places.empty()) return indent_of(net_->places.front().statement.offset);
    if (!net_->transitions.empty()) return indent_of(net_->transitions.front().extent.offset);
    return indent_of(net_->span.offset) + "  ";
  }

  // ---- places -----------------------------------------------------------------
  core::Result<void> add_place() {
    if (auto r = fresh_name(e_.name); !r) return r;
    const std::string decl =
        e_.value ? fmt::format("place {} = {};", e_.name, e_.value) : fmt::format("place {};", e_.name);
    // After the last place or exit statement, else before the first transition,
    // else before the closing brace.
    std::optional<std::uint32_t> after;
    for (const auto& p : net_->places) {
      after = std::max(after.value_or(0), p.statement.offset + p.statement.length);
    }
    if (after) {
      *after = past_line_comment(*after);
      splices_.push_back({*after, 0, "\n" + body_indent() + decl});
    } else if (!net_->transitions.empty()) {
      const std::uint32_t at = net_->transitions.front().extent.offset;
      splices_.push_back({at, 0, decl + "\n" + indent_of(at)});
    } else if (net_->body_end) {
      splices_.push_back({*net_->body_end, 0, "  " + decl + "\n" + indent_of(*net_->body_end)});
    } else {
      return invalid(fmt::format("net '{}' has no closing '}}' to add a place before", e_.net));
    }
    return {};
  }

  core::Result<void> delete_place() {
    const ast::PlaceDecl* p = place(e_.name);
    if (!p) return invalid(fmt::format("no place '{}' in net '{}'", e_.name, e_.net));
    // The declaration: the whole statement when it declares only this place.
    std::size_t in_statement = 0;
    for (const auto& q : net_->places) in_statement += q.statement.offset == p->statement.offset ? 1 : 0;
    if (in_statement == 1) {
      remove_lines(p->statement.offset, p->statement.length);
    } else {
      std::uint32_t begin = p->name.span.offset;
      std::uint32_t end = p->initial_span.length ? p->initial_span.offset + p->initial_span.length
                                                 : p->name.span.offset + p->name.span.length;
      // With the comma after it, or else the one before it.
      std::uint32_t after = end;
      while (after < text_.size() && (text_[after] == ' ' || text_[after] == '\t')) ++after;
      if (after < text_.size() && text_[after] == ',') {
        end = after + 1;
        while (end < text_.size() && (text_[end] == ' ' || text_[end] == '\t')) ++end;
      } else {
        while (begin > p->statement.offset && text_[begin - 1] != ',') --begin;
        if (begin > p->statement.offset) --begin;
      }
      splices_.push_back({begin, end - begin, ""});
    }
    // Its arcs: each transition that has one is printed again without them.
    for (const auto& t : net_->transitions) {
      auto uses = [&](const std::vector<ast::ArcRef>& arcs) {
        return std::any_of(arcs.begin(), arcs.end(), [&](const ast::ArcRef& a) { return a.place.text == e_.name; });
      };
      if (!uses(t.waits) && !uses(t.signals)) continue;
      Printed pt = printable(t);
      std::erase_if(pt.waits, [&](const auto& a) { return a.first == e_.name; });
      std::erase_if(pt.signals, [&](const auto& a) { return a.first == e_.name; });
      reprint(t, pt);
    }
    return {};
  }

  core::Result<void> rename_place() {
    const ast::PlaceDecl* p = place(e_.name);
    if (!p) return invalid(fmt::format("no place '{}' in net '{}'", e_.name, e_.net));
    if (auto r = fresh_name(e_.to); !r) return r;
    auto rename = [&](const ast::Name& n) {
      if (n.text == e_.name) splices_.push_back({n.span.offset, n.span.length, e_.to});
    };
    rename(p->name);
    for (const auto& t : net_->transitions) {
      for (const auto& a : t.waits) rename(a.place);
      for (const auto& a : t.signals) rename(a.place);
      for (const auto& action : t.actions) {
        if (const auto* tactic = std::get_if<ast::Tactic>(&action)) {
          for (const auto& n : tactic->places) rename(n);
        } else {
          for (const auto& n : std::get<ast::Phase>(action).places) rename(n);
        }
      }
    }
    return {};
  }

  core::Result<void> set_initial() {
    const ast::PlaceDecl* p = place(e_.name);
    if (!p) return invalid(fmt::format("no place '{}' in net '{}'", e_.name, e_.net));
    if (p->initial_span.length) {
      splices_.push_back({p->initial_span.offset, p->initial_span.length, std::to_string(e_.value)});
    } else if (e_.value != 0) {
      splices_.push_back({p->name.span.offset + p->name.span.length, 0, fmt::format(" = {}", e_.value)});
    }
    return {};
  }

  // ---- transitions --------------------------------------------------------------
  // A transition's parts, to print it again.
  struct Printed {
    std::vector<std::pair<std::string, std::uint32_t>> waits, signals;
    std::vector<std::string> actions;
  };
  Printed printable(const ast::Transition& t) const {
    Printed p;
    for (const auto& a : t.waits) p.waits.emplace_back(a.place.text, a.weight);
    for (const auto& a : t.signals) p.signals.emplace_back(a.place.text, a.weight);
    for (const auto& action : t.actions) {
      const core::SourceSpan& s = std::visit([](const auto& x) -> const core::SourceSpan& { return x.span; }, action);
      p.actions.emplace_back(slice(s));
    }
    return p;
  }
  static std::string arcs_text(const std::vector<std::pair<std::string, std::uint32_t>>& arcs) {
    std::string s;
    for (const auto& [place, w] : arcs)
      s += (s.empty() ? "" : ", ") + (w == 1 ? place : fmt::format("{}*{}", place, w));
    return s;
  }
  std::string transition_text(const std::string& name, int priority, const Printed& p,
                              const std::string& indent) const {
    std::string out = fmt::format("transition {}{} {{\n", name, priority ? fmt::format(" priority {}", priority) : "");
    if (!p.waits.empty()) out += fmt::format("{}  wait   {{ {} }}\n", indent, arcs_text(p.waits));
    if (!p.actions.empty()) {
      std::string joined;
      for (const auto& a : p.actions) {
        if (!joined.empty()) joined.append(",\n").append(indent).append("           ");
        joined += a;
      }
      out += fmt::format("{}  action {{ {} }}\n", indent, joined);
    }
    if (!p.signals.empty()) out += fmt::format("{}  signal {{ {} }}\n", indent, arcs_text(p.signals));
    return out + indent + "}";
  }
  void reprint(const ast::Transition& t, const Printed& p) {
    splices_.push_back(
        {t.extent.offset, t.extent.length, transition_text(t.name.text, t.priority, p, indent_of(t.extent.offset))});
  }

  core::Result<void> add_transition() {
    if (auto r = fresh_name(e_.name); !r) return r;
    if (!net_->body_end) return invalid(fmt::format("net '{}' has no closing '}}' to add a transition before", e_.net));
    const std::string indent = body_indent();
    const std::uint32_t at = line_start(*net_->body_end);
    const bool own_line = text_.substr(at, *net_->body_end - at).find_first_not_of(" \t") == std::string_view::npos;
    const std::string text = fmt::format("{}transition {} {{ }}\n", indent, e_.name);
    if (own_line) {
      splices_.push_back({at, 0, text});
    } else {
      splices_.push_back({*net_->body_end, 0, "\n" + text});
    }
    return {};
  }

  core::Result<void> delete_transition() {
    const ast::Transition* t = transition(e_.name);
    if (!t) return invalid(fmt::format("no transition '{}' in net '{}'", e_.name, e_.net));
    remove_lines(t->extent.offset, t->extent.length);
    return {};
  }

  core::Result<void> rename_transition() {
    const ast::Transition* t = transition(e_.name);
    if (!t) return invalid(fmt::format("no transition '{}' in net '{}'", e_.name, e_.net));
    if (auto r = fresh_name(e_.to); !r) return r;
    splices_.push_back({t->name.span.offset, t->name.span.length, e_.to});
    return {};
  }

  core::Result<void> arc() {
    // place -> transition: a wait arc; transition -> place: a signal arc.
    const ast::Transition* t = transition(e_.to);
    std::string place_name = e_.from;
    bool is_wait = true;
    if (!t || !place(e_.from)) {
      t = transition(e_.from);
      place_name = e_.to;
      is_wait = false;
    }
    if (!t || !place(place_name)) {
      return invalid(fmt::format("an arc joins a place and a transition of net '{}'; '{}' -> '{}' does not", e_.net,
                                 e_.from, e_.to));
    }
    Printed p = printable(*t);
    auto& arcs = is_wait ? p.waits : p.signals;
    auto it = std::find_if(arcs.begin(), arcs.end(), [&](const auto& a) { return a.first == place_name; });
    const std::uint32_t weight = e_.value == 0 ? 1 : e_.value;
    switch (e_.op) {
      case Op::AddArc:
        if (it != arcs.end()) return invalid(fmt::format("there is already an arc {} -> {}", e_.from, e_.to));
        arcs.emplace_back(place_name, weight);
        break;
      case Op::DeleteArc:
        if (it == arcs.end()) return invalid(fmt::format("there is no arc {} -> {}", e_.from, e_.to));
        arcs.erase(it);
        break;
      default:
        if (it == arcs.end()) return invalid(fmt::format("there is no arc {} -> {}", e_.from, e_.to));
        it->second = weight;
    }
    reprint(*t, p);
    return {};
  }

  core::Result<void> set_actions() {
    const ast::Transition* t = transition(e_.name);
    if (!t) return invalid(fmt::format("no transition '{}' in net '{}'", e_.name, e_.net));
    Printed p = printable(*t);
    p.actions = e_.actions;
    reprint(*t, p);
    return {};
  }

  std::string_view text_;
  const Edit& e_;
  core::SourceManager sources_;
  core::DiagnosticSink sink_;
  core::FileId id_ = 0;
  ast::File file_;
  const ast::Net* net_ = nullptr;
  std::vector<Splice> splices_;
};

}  // namespace

core::Result<std::string> apply_edit(std::string_view text, const Edit& edit) { return Editor(text, edit).run(); }

}  // namespace strata::coral
