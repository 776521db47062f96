#include "run/answers.h"

#include <algorithm>
#include <cctype>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "coral/checker.h"
#include "core/text.h"

namespace strata::run {
namespace {

using Json = nlohmann::json;

core::Error invalid(std::string message) { return core::make_error(core::ErrorCode::InvalidInput, std::move(message)); }

// Line and column (from 1) of byte offset `at` in text.
std::pair<std::size_t, std::size_t> line_col(std::string_view text, std::size_t at) {
  at = std::min(at, text.size());
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < at; ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return {line, col};
}

const std::set<std::string, std::less<>> kTopKeys{"strata_answers", "mission", "net", "from", "answers", "path"};
const std::set<std::string, std::less<>> kEntryKeys{"step", "net", "transition", "action", "primitive", "answer"};

std::string string_field(const Json& entry, const char* key, const std::string& where, bool required,
                         std::string& error) {
  auto it = entry.find(key);
  if (it == entry.end()) {
    if (required && error.empty()) error = fmt::format("{}: no \"{}\"", where, key);
    return {};
  }
  if (!it->is_string() || it->get_ref<const std::string&>().empty()) {
    if (error.empty()) error = fmt::format("{}: \"{}\" is not a name", where, key);
    return {};
  }
  return it->get<std::string>();
}

}  // namespace

std::string ScriptedAnswer::where() const {
  std::string about = step ? fmt::format("step {}, ", step) : std::string();
  about += fmt::format("{} {}", action, primitive);
  if (!transition.empty()) about += " in " + transition;
  if (!net.empty()) about += " of " + net;
  return fmt::format("answers[{}] ({})", index, about);
}

core::Result<AnswerScript> parse_answers(std::string_view text, const std::string& path) {
  if (text.size() > kMaxAnswersFileBytes) {
    return core::make_error(core::ErrorCode::Overflow,
                            fmt::format("{}: larger than {} bytes", path, kMaxAnswersFileBytes));
  }
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::parse_error& e) {
    auto [line, col] = line_col(text, e.byte > 0 ? e.byte - 1 : 0);
    std::string what = e.what();
    // "[json.exception.parse_error.101] parse error at line 1, column 3: syntax error ..."
    // text-ok: nlohmann's own prefix is cut for the reader; nothing is decided on it.
    if (auto colon = what.find(": "); colon != std::string::npos) what = what.substr(colon + 2);
    // And its quote of the text ("; last read: '...'"): the line and column
    // say where, and a file that is not what it was said to be (a campaign
    // spec's `answers` naming someone's secrets) is not shown.
    // text-ok: nlohmann's quote of the input is cut for the reader; nothing is decided on it.
    if (auto quoted = what.find("; last read:"); quoted != std::string::npos) what.resize(quoted);
    return invalid(fmt::format("{}:{}:{}: not JSON: {}", path, line, col, what));
  }
  if (!j.is_object()) return invalid(fmt::format("{}: not an answers file: the top is not an object", path));
  for (const auto& [key, value] : j.items()) {
    if (!kTopKeys.contains(key)) {
      return invalid(
          fmt::format("{}: unknown key \"{}\" (an answers file has strata_answers, mission, net, from, "
                      "answers, path)",
                      path, key));
    }
  }
  auto version = j.find("strata_answers");
  if (version == j.end() || !version->is_number_integer()) {
    return invalid(
        fmt::format("{}: not an answers file: no \"strata_answers\": 1 (`strata verify --witness-out` "
                    "writes one)",
                    path));
  }
  if (version->get<std::int64_t>() != 1) {
    return invalid(fmt::format("{}: \"strata_answers\": {} is a format this strata does not read (it reads 1)", path,
                               version->dump()));
  }
  AnswerScript script;
  script.path = path;
  for (auto [key, field] : {std::pair{"mission", &script.mission}, {"net", &script.net}, {"from", &script.from}}) {
    auto it = j.find(key);
    if (it == j.end()) continue;
    if (!it->is_string()) return invalid(fmt::format("{}: \"{}\" is not a string", path, key));
    *field = it->get<std::string>();
  }
  auto answers = j.find("answers");
  if (answers == j.end() || !answers->is_array()) {
    return invalid(fmt::format("{}: no \"answers\" array", path));
  }
  if (answers->size() > kMaxAnswers) {
    return invalid(fmt::format("{}: {} answers: at most {} are read", path, answers->size(), kMaxAnswers));
  }
  for (std::size_t i = 0; i < answers->size(); ++i) {
    const Json& e = (*answers)[i];
    const std::string where = fmt::format("{}: answers[{}]", path, i);
    if (!e.is_object()) return invalid(where + ": not an object");
    for (const auto& [key, value] : e.items()) {
      if (!kEntryKeys.contains(key)) {
        return invalid(
            fmt::format("{}: unknown key \"{}\" (an answer has step, net, transition, action, primitive, "
                        "answer)",
                        where, key));
      }
    }
    ScriptedAnswer a;
    a.index = i;
    std::string error;
    a.net = string_field(e, "net", where, false, error);
    a.transition = string_field(e, "transition", where, false, error);
    a.action = string_field(e, "action", where, true, error);
    a.primitive = string_field(e, "primitive", where, true, error);
    if (!error.empty()) return invalid(error);
    if (auto step = e.find("step"); step != e.end()) {
      if (!step->is_number_unsigned()) return invalid(where + ": \"step\" is not a step number (1, 2, ...)");
      a.step = step->get<std::size_t>();
    }
    if (a.action != "exec" && a.action != "ask" && a.action != "ood" && a.action != "phase") {
      return invalid(
          fmt::format("{}: \"action\": \"{}\" is not one of exec, ask, ood, phase (a report waits for no "
                      "answer)",
                      where, a.action));
    }
    if (!a.transition.empty() && a.net.empty()) return invalid(where + ": a \"transition\" needs its \"net\"");
    auto answer = e.find("answer");
    if (answer == e.end()) return invalid(where + ": no \"answer\"");
    if (a.action == "phase") {
      if (a.net.empty() || a.transition.empty()) {
        return invalid(where + ": a phase's answer needs the \"net\" and \"transition\" that run it");
      }
      if (!answer->is_string() || answer->get_ref<const std::string&>().empty()) {
        return invalid(where + ": a phase's \"answer\" is the name of the exit it ends at");
      }
      a.exit = answer->get<std::string>();
    } else {
      if (!answer->is_number_integer() || (answer->get<std::int64_t>() != 0 && answer->get<std::int64_t>() != 1)) {
        return invalid(fmt::format("{}: \"answer\": {} is not 0 or 1", where, answer->dump()));
      }
      a.value = answer->get<std::int64_t>() == 1;
    }
    script.answers.push_back(std::move(a));
  }
  return script;
}

core::Result<void> check_answers(const AnswerScript& script, const tactical::Catalogue& catalogue,
                                 const coral::Program* program) {
  std::vector<std::string> names;
  for (const auto& p : catalogue.all()) names.push_back(p.name);
  for (const ScriptedAnswer& a : script.answers) {
    const std::string where = fmt::format("{}: {}", script.path, a.where());
    if (a.action != "phase") {
      const tactical::Primitive* p = catalogue.find(a.primitive);
      if (!p) {
        auto s = core::suggest(a.primitive, names);
        return invalid(fmt::format("{}: unknown primitive '{}'{}", where, a.primitive,
                                   s ? fmt::format(" (did you mean '{}'?)", *s) : std::string()));
      }
      if (core::call_verb_name(p->kind) != a.action) {
        return invalid(fmt::format("{}: '{}' is an {} primitive, not {}", where, a.primitive,
                                   core::call_verb_name(p->kind), a.action));
      }
    }
    if (!program) {
      if (!a.net.empty()) {
        return invalid(fmt::format("{}: PROLOG rules have no nets: leave out \"net\" and \"transition\"", where));
      }
      if (a.action == "phase") return invalid(where + ": a phase's exit is checked on CORAL missions only");
      continue;
    }
    if (a.net.empty()) continue;
    std::vector<std::string> nets;
    for (const auto& n : program->nets) nets.push_back(n.name);
    const coral::CompiledNet* net = program->find(a.net);
    if (!net) {
      auto s = core::suggest(a.net, nets);
      return invalid(fmt::format("{}: the mission has no net '{}'{}", where, a.net,
                                 s ? fmt::format(" (did you mean '{}'?)", *s) : std::string()));
    }
    if (a.transition.empty()) continue;
    auto t = net->net.find_transition(a.transition);
    if (!t) {
      return invalid(fmt::format("{}: net '{}' has no transition '{}'", where, a.net, a.transition));
    }
    const auto& actions = net->actions[*t];
    const auto action = std::find_if(actions.begin(), actions.end(), [&](const coral::ActionSpec& s) {
      const bool phase = s.kind == coral::ActionSpec::Kind::Phase;
      if (phase != (a.action == "phase") || s.target != a.primitive) return false;
      if (phase) return true;
      std::string kind(coral::tactic_type_name(s.tactic));
      std::transform(kind.begin(), kind.end(), kind.begin(), [](unsigned char c) { return std::tolower(c); });
      return kind == a.action;
    });
    if (action == actions.end()) {
      return invalid(fmt::format("{}: transition '{}' of '{}' has no {} {} action", where, a.transition, a.net,
                                 a.action == "phase" ? "PHASE" : a.action, a.primitive));
    }
    if (a.action == "phase") {
      const coral::CompiledNet* phase = program->find(a.primitive);
      const bool known = phase && std::any_of(phase->exits.begin(), phase->exits.end(),
                                              [&](petri::PlaceId p) { return phase->net.place_name(p) == a.exit; });
      if (!known) return invalid(fmt::format("{}: phase '{}' has no exit '{}'", where, a.primitive, a.exit));
    }
  }
  return {};
}

}  // namespace strata::run
