#include "core/call_verb.h"

namespace strata::core {

std::string_view call_verb_name(CallVerb verb) {
  switch (verb) {
    case CallVerb::Exec: return "exec";
    case CallVerb::Ask: return "ask";
    case CallVerb::Ood: return "ood";
    case CallVerb::Report: return "report";
  }
  return "?";
}

std::optional<CallVerb> parse_call_verb(std::string_view name) {
  for (CallVerb v : kCallVerbs) {
    if (call_verb_name(v) == name) return v;
  }
  return std::nullopt;
}

}  // namespace strata::core
