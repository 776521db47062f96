// Writing PNML: write_pnml (pnml.h).
#include "petri/pnml.h"

#include <cstdint>
#include <iterator>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include <fmt/format.h>

namespace strata::petri {
namespace {

constexpr std::string_view kPnmlNamespace = "http://www.pnml.org/version-2009/grammar/pnml";

// Ids for write_pnml: NCNames (ASCII letters, digits, '_', '-', '.', not
// starting with a digit, '-' or '.'), unique in the document.
class IdMaker {
 public:
  std::string make(std::string_view name) {
    auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
    std::string id = !name.empty() && letter(name[0]) ? "" : "_";
    for (char c : name) {
      id += letter(c) || (c >= '0' && c <= '9') || c == '-' || c == '.' ? c : '_';
    }
    if (used_.insert(id).second) return id;
    // Suffixes from _2 on; the counter spares a rescan from _2 each time.
    for (std::uint32_t& n = next_suffix_.try_emplace(id, 1).first->second;;) {
      std::string candidate = fmt::format("{}_{}", id, ++n);
      if (used_.insert(candidate).second) return candidate;
    }
  }

 private:
  std::unordered_set<std::string> used_;
  std::unordered_map<std::string, std::uint32_t> next_suffix_;
};

// Character data for a <text>: markup characters escaped, and control
// characters as references so that they come back unchanged.
void append_text(std::string& out, std::string_view s) {
  for (char c : s) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (static_cast<unsigned char>(c) >= 0x20 || c == '\t' || c == '\n')
      out += c;
    else
      fmt::format_to(std::back_inserter(out), "&#{};", int{c});
  }
}

}  // namespace

std::string write_pnml(const Net& net, const std::string& net_id) {
  // Places and transitions take their ids first, so that names which are
  // already unique XML names are kept as they are.
  IdMaker ids;
  std::vector<std::string> place_ids, transition_ids;
  for (PlaceId p = 0; p < net.place_count(); ++p) place_ids.push_back(ids.make(net.place_name(p)));
  for (TransitionId t = 0; t < net.transition_count(); ++t) {
    transition_ids.push_back(ids.make(net.transition_name(t)));
  }
  std::string out;
  auto o = std::back_inserter(out);
  fmt::format_to(o,
                 "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<pnml xmlns=\"{}\">\n"
                 "  <net id=\"{}\" type=\"{}\">\n    <name><text>",
                 kPnmlNamespace, ids.make(net_id), kPtNetType);
  append_text(out, net_id);
  fmt::format_to(o, "</text></name>\n    <page id=\"{}\">\n", ids.make("page"));
  for (PlaceId p = 0; p < net.place_count(); ++p) {
    fmt::format_to(o, "      <place id=\"{}\"><name><text>", place_ids[p]);
    append_text(out, net.place_name(p));
    out += "</text></name>";
    if (Tokens m = net.initial_marking()[p]; m != 0) {
      fmt::format_to(o, "<initialMarking><text>{}</text></initialMarking>", m);
    }
    out += "</place>\n";
  }
  for (TransitionId t = 0; t < net.transition_count(); ++t) {
    fmt::format_to(o, "      <transition id=\"{}\"><name><text>", transition_ids[t]);
    append_text(out, net.transition_name(t));
    out += "</text></name></transition>\n";
  }
  std::uint64_t arcs = 0;
  auto write_arc = [&](const std::string& source, const std::string& target, std::uint32_t weight) {
    fmt::format_to(o, "      <arc id=\"{}\" source=\"{}\" target=\"{}\"", ids.make(fmt::format("a{}", ++arcs)), source,
                   target);
    if (weight == 1)
      out += "/>\n";
    else
      fmt::format_to(o, "><inscription><text>{}</text></inscription></arc>\n", weight);
  };
  for (TransitionId t = 0; t < net.transition_count(); ++t) {
    for (const Arc& a : net.inputs(t)) write_arc(place_ids[a.node], transition_ids[t], a.weight);
    for (const Arc& a : net.outputs(t)) write_arc(transition_ids[t], place_ids[a.node], a.weight);
  }
  out += "    </page>\n  </net>\n</pnml>\n";
  return out;
}

}  // namespace strata::petri
