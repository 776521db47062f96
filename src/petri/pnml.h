#pragma once
// PNML (ISO/IEC 15909-2) for place/transition nets: import into a
// petri::Net and export from one (docs/verification.md).
//
// Import: the document holds exactly one <net>, of type ptnet
// (http://www.pnml.org/version-2009/grammar/ptnet). Every <page> is read,
// nested pages too, in document order: that order numbers the places and the
// transitions. <referencePlace> and <referenceTransition> nodes stand for the
// node they reference (followed through chains of references) and arcs to
// them go to that node. A node is known by its id (unique in a PNML
// document): the Net's place and transition names are the ids, and the
// <name><text> labels, which need not be unique, are kept beside them (the
// id when there is no <name><text>; an empty text stays empty). A missing
// <inscription> is weight 1, a missing <initialMarking> is 0 tokens; numbers
// may have whitespace around them. Two arcs between the same place and
// transition in the same direction add up. <graphics> and <toolspecific> are
// skipped. Anything else Strata does not support is an error, never dropped:
// a net type other than P/T (e.g. a coloured net), an inhibitor, read or
// reset arc, an element P/T nets do not have (e.g. <capacity>), an arc
// between two places or two transitions, an arc or reference to an unknown
// node, a reference cycle, an inscription that is not a positive integer, a
// marking that is not a non-negative integer, or either over kMaxTokens (also
// when parallel arcs add up to more).
//
// Errors: InvalidInput with "path:line:col: message" (the '<' of the
// offending element, or where the XML parser stopped; columns count bytes),
// or Io when the file cannot be read.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "petri/net.h"

namespace strata::petri {

struct PnmlNet {
  Net net;                                     // places and transitions named by their PNML ids
  std::string id;                              // the <net id="...">
  std::string name;                            // the net's <name><text>, or its id
  std::vector<std::string> place_labels;       // by PlaceId: the <name><text>, or the id
  std::vector<std::string> transition_labels;  // by TransitionId
};

// The type of a place/transition net's <net>.
inline constexpr std::string_view kPtNetType = "http://www.pnml.org/version-2009/grammar/ptnet";

// The largest PNML file read.
inline constexpr std::size_t kMaxPnmlBytes = std::size_t{64} << 20;

// Reads a PNML file (core::read_regular_file: a FIFO or a device is refused,
// a file over kMaxPnmlBytes too) and parses it.
core::Result<PnmlNet> read_pnml(const std::string& path);
// The same from text; source_name labels the errors.
core::Result<PnmlNet> parse_pnml(const std::string& text, const std::string& source_name);

// The net as PNML 2009 P/T text: one page; ids are the Net's names, made
// XML-safe (bytes other than ASCII letters, digits, '_', '-', '.' become '_',
// with a '_' in front when needed) and unique (a "_2", "_3" suffix) when
// they are not already; every node also gets its name as <name><text>.
// Weights other than 1 and initial markings other than 0 are written out;
// priorities are not (P/T PNML has none). parse_pnml of the result gives the
// same net: the same places and transitions in the same order, arcs, weights
// and marking, with the names as labels (and as ids when they were safe).
std::string write_pnml(const Net& net, const std::string& net_id);

}  // namespace strata::petri
