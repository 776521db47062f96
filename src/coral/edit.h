#pragma once
// Structural edits of CORAL text, for the studio's editor (docs/studio.md):
// each edit is applied to the text itself, so the text stays the source of
// truth. Only the element an edit touches is rewritten; everything else,
// comments included, is kept byte for byte. A transition that an edit
// changes (an arc, a weight, its actions) is printed again whole, in the
// standard layout, and comments inside it are lost; renaming touches only
// the names.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace strata::coral {

struct Edit {
  enum class Op {
    AddPlace,          // net, name, value = initial marking
    DeletePlace,       // net, name (its arcs go too)
    RenamePlace,       // net, name, to (every use in the net)
    SetInitial,        // net, name, value
    AddTransition,     // net, name
    DeleteTransition,  // net, name
    RenameTransition,  // net, name, to
    AddArc,            // net, from, to, value = weight: place -> transition waits, transition -> place signals
    DeleteArc,         // net, from, to
    SetWeight,         // net, from, to, value
    SetActions,        // net, name = the transition, actions = each action as CORAL text
  };
  Op op = Op::AddPlace;
  std::string net;
  std::string name;
  std::string to;
  std::string from;
  std::uint32_t value = 0;
  std::vector<std::string> actions;  // "TACTIC(EXEC, sleep(1), done)", "PHASE(p, a, b)"
};

// The text with the edit applied; InvalidInput (with why) when the net,
// place or transition is not there, a new name is taken or not a name, an
// arc joins two places or two transitions, or the text around it does not
// parse well enough to edit.
core::Result<std::string> apply_edit(std::string_view text, const Edit& edit);

}  // namespace strata::coral
