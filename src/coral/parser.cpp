#include "coral/parser.h"

#include <algorithm>
#include <initializer_list>
#include <limits>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "coral/guards.h"
#include "coral/lexer.h"
#include "coral/program.h"
#include "coral/token_cursor.h"

namespace strata::coral {
namespace {

using core::DiagnosticKind;
using TK = TokenKind;

// The grammar (docs/coral.md), over the token cursor's plumbing and recovery.
class Parser : private TokenCursor {
 public:
  Parser(const core::SourceManager& sources, core::FileId id, core::DiagnosticSink& sink)
      : TokenCursor(id, sources.text(id), sink) {
    file_.id = id;
  }

  ast::File parse_file() {
    while (!at(TK::EndOfFile)) {
      panic_ = false;
      if (match(TK::KwImport)) {
        parse_import();
      } else if (at(TK::KwNet) || at(TK::KwMission)) {
        parse_net();
      } else {
        error_here("expected 'net', 'mission' or 'import' at the top level");
        // Skip to the next top-level declaration.
        while (!at(TK::EndOfFile) && !at(TK::KwNet) && !at(TK::KwMission) && !at(TK::KwImport)) {
          advance();
        }
      }
    }
    return std::move(file_);
  }

 private:
  // --- declarations -----------------------------------------------------------
  void parse_import() {
    Token head = prev_;
    if (at(TK::Identifier)) {  // `import NAME;`: a module of the phase library
      file_.imports.push_back({std::string(tok_.text), join(head.span, tok_.span), true});
    } else if (at(TK::String)) {
      file_.imports.push_back({unescape(tok_.text), join(head.span, tok_.span)});
    } else {
      error_here("expected a file name in quotes or a library module's name after 'import'");
      recover(TK::Semicolon);
      return;
    }
    advance();
    if (!expect(TK::Semicolon, "after the import")) recover(TK::Semicolon);
  }

  void parse_net() {
    ast::Net net;
    net.kind = at(TK::KwMission) ? ast::Net::Kind::Mission : ast::Net::Kind::Phase;
    Token head = tok_;
    advance();
    auto n = name(net.kind == ast::Net::Kind::Mission ? "a mission name" : "a net name");
    if (!n) {
      recover(TK::RBrace);
      return;
    }
    net.name = *n;
    net.span = join(head.span, n->span);
    if (match(TK::LParen)) parse_params(net);
    params_ = &net.params;  // for TACTIC(REPORT, name) in the body
    // A missing '{' is reported, then the body is parsed as if it were there.
    bool opened = expect(TK::LBrace, "to open the net body");
    while (!at(TK::RBrace) && !at(TK::EndOfFile) && !at(TK::KwNet) && !at(TK::KwMission) && !at(TK::KwImport)) {
      if (opened) panic_ = false;
      opened = true;
      if (match(TK::KwPlace)) {
        parse_places(net, false);
      } else if (match(TK::KwExit)) {
        parse_places(net, true);
      } else if (match(TK::KwData)) {
        parse_data(net);
      } else if (match(TK::KwTransition)) {
        parse_transition(net);
      } else if (match(TK::KwGuard)) {
        parse_guard(net);
      } else if (at(TK::Identifier) && tok_.text == "require") {
        // `require` is not a keyword: it means something only here.
        advance();
        if (!at(TK::String)) {
          error_here(
              "expected the requirement in quotes after 'require': \"fault system_problem -> surface within 60\"");
          recover(TK::Semicolon);
          continue;
        }
        net.requirements.push_back(literal());
        if (!expect(TK::Semicolon, "after the requirement")) recover(TK::Semicolon);
      } else {
        error_here("expected 'place', 'exit', 'data', 'transition', 'guard', 'require' or '}' in the net body");
        recover(TK::Semicolon);
      }
    }
    if (!at(TK::RBrace)) {
      error_at(tok_,
               fmt::format("expected '}}' to close {} '{}', found {}",
                           net.kind == ast::Net::Kind::Mission ? "mission" : "net", net.name.text, describe(tok_)));
    } else {
      net.body_end = tok_.span.offset;
      advance();
    }
    params_ = nullptr;
    file_.nets.push_back(std::move(net));
  }

  // After `net NAME (`: `[number | string] NAME {, ...} )`. The type words
  // are not keywords: a parameter may be called `number`.
  void parse_params(ast::Net& net) {
    if (net.kind == ast::Net::Kind::Mission) {
      error_at(prev_, fmt::format("mission '{}' cannot take parameters: only a phase net does", net.name.text));
      recover(TK::RParen);
      return;
    }
    if (match(TK::RParen)) return;
    do {
      auto first = name("a parameter name");
      if (!first) {
        recover(TK::RParen);
        return;
      }
      ast::Param param{*first, ast::ParamType::Number, first->span};
      if (at(TK::Identifier)) {  // `TYPE NAME`
        if (first->text == "string") {
          param.type = ast::ParamType::String;
        } else if (first->text != "number") {
          error_at(prev_, fmt::format("unknown parameter type '{}': a parameter is a number or a string", first->text));
          recover(TK::RParen);
          return;
        }
        param.name = {std::string(tok_.text), tok_.span};
        param.span = join(first->span, tok_.span);
        advance();
      }
      if (net.params.size() == kMaxArguments) {
        sink_.report(DiagnosticKind::TooManyArguments, param.span,
                     fmt::format("net '{}' declares more than {} parameters", net.name.text, kMaxArguments));
        recover(TK::RParen);
        return;
      }
      net.params.push_back(std::move(param));
    } while (match(TK::Comma));
    if (!expect(TK::RParen, "to close the parameters")) recover(TK::RParen);
  }

  void parse_places(ast::Net& net, bool is_exit) {
    const Token head = prev_;  // `place` or `exit`
    const std::size_t first = net.places.size();
    do {
      auto n = name(is_exit ? "an exit place name" : "a place name");
      if (!n) {
        recover(TK::Semicolon);
        return;
      }
      ast::PlaceDecl decl{*n, 0, is_exit, false, {}, {}};
      if (match(TK::Equals)) {
        decl.initial = integer(0, std::numeric_limits<std::uint32_t>::max(), DiagnosticKind::BadWeight,
                               "an initial mark", &decl.initial_span);
      }
      if (is_exit) net.exits.push_back(decl.name);
      net.places.push_back(std::move(decl));
    } while (match(TK::Comma));
    if (!expect(TK::Semicolon, is_exit ? "after the exit places" : "after the places")) {
      recover(TK::Semicolon);
    }
    for (std::size_t i = first; i < net.places.size(); ++i) net.places[i].statement = join(head.span, prev_.span);
  }

  void parse_data(ast::Net& net) {
    if (!at(TK::String)) {
      error_here("expected a file name in quotes after 'data'");
      recover(TK::Semicolon);
      return;
    }
    net.data.push_back(literal());
    if (!expect(TK::Semicolon, "after the data file")) recover(TK::Semicolon);
  }

  void parse_transition(ast::Net& net) {
    Token head = prev_;
    auto n = name("a transition name");
    if (!n) {
      recover(TK::RBrace);
      return;
    }
    ast::Transition t;
    t.name = *n;
    t.span = join(head.span, n->span);
    if (match(TK::KwPriority)) t.priority = priority();
    if (!expect(TK::LBrace, "to open the transition body")) {
      recover(TK::RBrace);
      t.extent = join(head.span, prev_.span);
      net.transitions.push_back(std::move(t));
      return;
    }
    bool seen_wait = false, seen_action = false, seen_signal = false;
    while (!at(TK::RBrace) && !at(TK::EndOfFile) && !is_declaration_keyword(tok_.kind)) {
      panic_ = false;
      Token clause = tok_;
      auto once = [&](bool& seen) {
        if (seen) {
          sink_.report(
              DiagnosticKind::DuplicateClause, clause.span,
              fmt::format("transition '{}' has more than one '{}' clause; merge them", t.name.text, clause.text));
        }
        seen = true;
      };
      if (match(TK::KwWait)) {
        once(seen_wait);
        parse_arcs(t.waits);
      } else if (match(TK::KwAction)) {
        once(seen_action);
        parse_actions(t.actions);
      } else if (match(TK::KwSignal)) {
        once(seen_signal);
        parse_arcs(t.signals);
      } else {
        error_here("expected 'wait', 'action', 'signal' or '}' in the transition body");
        if (recover(TK::RBrace, true)) {  // consumed the transition's own '}'
          t.extent = join(head.span, prev_.span);
          net.transitions.push_back(std::move(t));
          return;
        }
      }
    }
    if (!expect(TK::RBrace, fmt::format("to close transition '{}'", t.name.text))) {
      recover(TK::RBrace, true);
    }
    t.extent = join(head.span, prev_.span);
    net.transitions.push_back(std::move(t));
  }

  // After `guard`: NAME every PERIOD { when { TERM, ... } action { ... } signal { ... } }.
  // `every`, `when` and `not` are not keywords: they mean something only here.
  void parse_guard(ast::Net& net) {
    Token head = prev_;
    auto n = name("a guard name");
    if (!n) {
      recover(TK::RBrace, true);
      return;
    }
    ast::Guard g;
    g.name = *n;
    g.span = join(head.span, n->span);
    auto give_up = [&] {
      recover(TK::RBrace, true);
      g.extent = join(head.span, prev_.span);
      net.guards.push_back(std::move(g));
    };
    if (!(at(TK::Identifier) && tok_.text == "every")) {
      error_here(fmt::format("expected 'every' and the poll period in seconds after guard '{}'", g.name.text));
      return give_up();
    }
    advance();
    if (at(TK::Integer) || at(TK::Float)) {
      g.period = literal();
    } else if (at(TK::Identifier)) {
      g.period = {ast::Literal::Kind::Parameter, std::string(tok_.text), std::string(tok_.text), tok_.span};
      advance();
    } else {
      error_here("expected the poll period in seconds (a number, or a number parameter of the net) after 'every'");
      return give_up();
    }
    if (!expect(TK::LBrace, "to open the guard body")) return give_up();
    bool seen_when = false, seen_action = false, seen_signal = false;
    while (!at(TK::RBrace) && !at(TK::EndOfFile) && !is_declaration_keyword(tok_.kind)) {
      panic_ = false;
      Token clause = tok_;
      auto once = [&](bool& seen) {
        if (seen) {
          sink_.report(DiagnosticKind::DuplicateClause, clause.span,
                       fmt::format("guard '{}' has more than one '{}' clause; merge them", g.name.text, clause.text));
        }
        seen = true;
      };
      if (at(TK::Identifier) && tok_.text == "when") {
        advance();
        once(seen_when);
        parse_terms(g.when);
      } else if (match(TK::KwAction)) {
        once(seen_action);
        parse_actions(g.actions);
      } else if (match(TK::KwSignal)) {
        once(seen_signal);
        parse_arcs(g.signals);
      } else {
        error_here("expected 'when', 'action', 'signal' or '}' in the guard body");
        if (recover(TK::RBrace, true)) {
          g.extent = join(head.span, prev_.span);
          net.guards.push_back(std::move(g));
          return;
        }
      }
    }
    if (!expect(TK::RBrace, fmt::format("to close guard '{}'", g.name.text))) recover(TK::RBrace, true);
    if (!seen_when) {
      sink_.report(DiagnosticKind::UnexpectedToken, g.name.span,
                   fmt::format("guard '{}' has no 'when' clause: say which ASKs trip it", g.name.text));
    }
    g.extent = join(head.span, prev_.span);
    if (net.guards.size() == kMaxGuards) {
      sink_.report(DiagnosticKind::TooManyGuards, g.name.span,
                   fmt::format("net '{}' declares more than {} guards; each one adds a transition per place of the "
                               "net",
                               net.name.text, kMaxGuards));
      return;
    }
    net.guards.push_back(std::move(g));
  }

  // `{ [not] ask [(args)], ... }`: at least one term.
  void parse_terms(std::vector<ast::GuardTerm>& out) {
    if (!expect(TK::LBrace, "to open the guard's condition")) {
      recover(TK::RBrace, true);
      return;
    }
    do {
      ast::GuardTerm term;
      Token first = tok_;
      if (at(TK::Identifier) && tok_.text == "not") {
        advance();
        term.negated = true;
      }
      if (!at(TK::Identifier)) {
        error_here("expected an ASK primitive (or 'not' and an ASK primitive) in the guard's condition");
        recover(TK::RBrace, true);
        return;
      }
      auto call = parse_call();
      if (!call) {
        recover(TK::RBrace, true);
        return;
      }
      term.ask = std::move(*call);
      term.span = join(first.span, prev_.span);
      out.push_back(std::move(term));
    } while (match(TK::Comma));
    if (!expect(TK::RBrace, "to close the guard's condition (terms are separated by ',')")) {
      recover(TK::RBrace, true);
    }
  }

  void parse_arcs(std::vector<ast::ArcRef>& out) {
    if (!expect(TK::LBrace, "to open the place list")) {
      recover(TK::RBrace, true);
      return;
    }
    if (match(TK::RBrace)) return;
    do {
      auto n = name("a place name");
      if (!n) {
        recover(TK::RBrace, true);
        return;
      }
      ast::ArcRef arc{*n, 1, n->span};
      if (match(TK::Star)) {
        core::SourceSpan w{};
        arc.weight =
            integer(1, std::numeric_limits<std::uint32_t>::max(), DiagnosticKind::BadWeight, "an arc weight", &w);
        arc.span = join(n->span, w.length ? w : n->span);
      }
      out.push_back(std::move(arc));
    } while (match(TK::Comma));
    if (!expect(TK::RBrace, "to close the place list (places are separated by ',')")) {
      recover(TK::RBrace, true);
    }
  }

  void parse_actions(std::vector<ast::Action>& out) {
    if (!expect(TK::LBrace, "to open the action list")) {
      recover(TK::RBrace, true);
      return;
    }
    if (match(TK::RBrace)) return;
    do {
      if (match(TK::KwTactic)) {
        auto a = parse_tactic();
        if (!a) {
          recover(TK::RBrace, true);
          return;
        }
        out.emplace_back(std::move(*a));
      } else if (match(TK::KwPhase)) {
        auto a = parse_phase();
        if (!a) {
          recover(TK::RBrace, true);
          return;
        }
        out.emplace_back(std::move(*a));
      } else {
        error_here("expected TACTIC(...) or PHASE(...)");
        recover(TK::RBrace, true);
        return;
      }
    } while (match(TK::Comma));
    if (!expect(TK::RBrace, "to close the action list (actions are separated by ',')")) {
      recover(TK::RBrace, true);
    }
  }

  // After TACTIC: (TYPE, function-or-string {, place}).
  std::optional<ast::Tactic> parse_tactic() {
    Token head = prev_;
    if (!expect(TK::LParen, "after TACTIC")) return std::nullopt;
    ast::Tactic a;
    auto type = name("a TACTIC type: EXEC, ASK, REPORT or OOD");
    if (!type) return std::nullopt;
    a.type_name = *type;
    a.type = parse_tactic_type(type->text);
    if (!a.type) {
      sink_.report(DiagnosticKind::UnknownTacticType, type->span,
                   fmt::format("unknown TACTIC type '{}'; expected EXEC, ASK, REPORT or OOD", type->text));
    }
    if (!expect(TK::Comma, "after the TACTIC type")) return std::nullopt;
    if (at(TK::String)) {
      ast::Literal text = literal();
      if (a.type && *a.type != ast::TacticType::Report) {
        sink_.report(DiagnosticKind::TacticArguments, text.span,
                     fmt::format("TACTIC({}, ...) takes a primitive name, not a string", a.type_name.text));
      }
      a.text = std::move(text);
    } else if (at(TK::Identifier)) {
      auto call = parse_call();
      if (!call) return std::nullopt;
      if (a.type == ast::TacticType::Report && !call->has_parens && is_param(call->name.text)) {
        // `TACTIC(REPORT, label)`: a parameter of the net (the checker
        // wants it to be a string one).
        a.text = ast::Literal{ast::Literal::Kind::Parameter, call->name.text, call->name.text, call->name.span};
      } else {
        if (a.type == ast::TacticType::Report) {
          sink_.report(DiagnosticKind::TacticArguments, call->span,
                       call->has_parens ? std::string("TACTIC(REPORT, ...) takes a string in quotes, or a string "
                                                      "parameter of its net")
                                        : fmt::format("TACTIC(REPORT, ...) takes a string in quotes, or a string "
                                                      "parameter of its net; '{}' is neither",
                                                      call->name.text));
        }
        a.function = std::move(*call);
      }
    } else {
      error_here(a.type == ast::TacticType::Report ? "expected a string in quotes" : "expected a primitive name");
      return std::nullopt;
    }
    while (match(TK::Comma)) {
      auto p = name("a place name");
      if (!p) return std::nullopt;
      if (at(TK::LParen)) {
        error_here(fmt::format("expected ',' or ')' after place '{}' (places take no arguments)", p->text));
        return std::nullopt;
      }
      a.places.push_back(std::move(*p));
    }
    if (!expect(TK::RParen, "to close TACTIC(...)")) return std::nullopt;
    a.span = join(head.span, prev_.span);
    return a;
  }

  std::optional<ast::Phase> parse_phase() {
    Token head = prev_;
    if (!expect(TK::LParen, "after PHASE")) return std::nullopt;
    ast::Phase a;
    auto n = name("a phase name");
    if (!n) return std::nullopt;
    a.phase = *n;
    if (match(TK::LParen)) {
      a.has_parens = true;
      if (!arguments(a.args, n->text)) return std::nullopt;
    }
    while (match(TK::Comma)) {
      auto p = name("a place name");
      if (!p) return std::nullopt;
      a.places.push_back(std::move(*p));
    }
    if (!expect(TK::RParen, "to close PHASE(...)")) return std::nullopt;
    a.span = join(head.span, prev_.span);
    return a;
  }

  bool is_param(std::string_view name) const {
    if (!params_) return false;
    return std::any_of(params_->begin(), params_->end(), [&](const ast::Param& p) { return p.name.text == name; });
  }

  std::optional<ast::Call> parse_call() {
    ast::Call call;
    call.name = {std::string(tok_.text), tok_.span};
    advance();
    call.span = call.name.span;
    if (match(TK::LParen)) {
      call.has_parens = true;
      if (!arguments(call.args, call.name.text)) return std::nullopt;
      call.span = join(call.name.span, prev_.span);
    }
    return call;
  }

  // After `f(`: literals or parameter names, then ')'. At most kMaxArguments.
  bool arguments(std::vector<ast::Literal>& out, const std::string& callee) {
    if (match(TK::RParen)) return true;
    do {
      if (at(TK::Identifier)) {
        out.push_back({ast::Literal::Kind::Parameter, std::string(tok_.text), std::string(tok_.text), tok_.span});
        advance();
      } else if (at(TK::Integer) || at(TK::Float) || at(TK::String)) {
        out.push_back(literal());
      } else {
        error_here("expected an argument (a number, a string or a parameter's name)");
        return false;
      }
      if (out.size() > kMaxArguments) {
        sink_.report(DiagnosticKind::TooManyArguments, out.back().span,
                     fmt::format("'{}' is given more than {} arguments", callee, kMaxArguments));
        recover(TK::RParen);
        return false;
      }
    } while (match(TK::Comma));
    return expect(TK::RParen, fmt::format("to close the arguments of '{}'", callee));
  }

  ast::File file_;
  const std::vector<ast::Param>* params_ = nullptr;  // the net being parsed
};

}  // namespace

ast::File parse(const core::SourceManager& sources, core::FileId id, core::DiagnosticSink& sink) {
  std::string_view text = sources.text(id);
  if (text.size() > kMaxSourceSize) {
    sink.report(DiagnosticKind::FileTooLarge, {id, 0, 0},
                fmt::format("file is {} bytes; the limit is {}", text.size(), kMaxSourceSize));
    ast::File f;
    f.id = id;
    return f;
  }
  return Parser(sources, id, sink).parse_file();
}

}  // namespace strata::coral
