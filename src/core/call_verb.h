#pragma once
// The verb of a primitive call, one enum from the catalogue to the wire
// (docs/protocol.md, docs/language.md §7): the catalogue's `kind`, CORAL's
// TACTIC type, the rendered call, the executors' actions and the protocol's
// call verbs are all this. exec, ask and ood go to the vehicle; report never
// leaves the Tactical level.
//
// call_verb_name() is the one spelling: the catalogue file, PROLOG's
// primitive/4 facts, the mission log and the console all print through it.
#include <array>
#include <optional>
#include <string_view>

namespace strata::core {

enum class CallVerb { Exec, Ask, Ood, Report };

inline constexpr std::array<CallVerb, 4> kCallVerbs{CallVerb::Exec, CallVerb::Ask, CallVerb::Ood, CallVerb::Report};

// "exec", "ask", "ood", "report".
std::string_view call_verb_name(CallVerb verb);
// The verb spelled exactly so (lower case); nullopt for anything else.
std::optional<CallVerb> parse_call_verb(std::string_view name);

}  // namespace strata::core
