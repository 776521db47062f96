// Reading PNML: parse_pnml and read_pnml (pnml.h).
#include "petri/pnml.h"

#include <algorithm>
#include <optional>
#include <string_view>
#include <unordered_map>

#include <fmt/format.h>
#include <pugixml.hpp>

#include "core/file.h"

namespace strata::petri {
namespace {

// Element names without a namespace prefix: PNML is usually written with a
// default namespace, but <pnml:place> means the same.
std::string_view local_name(pugi::xml_node n) {
  std::string_view name = n.name();
  std::size_t colon = name.find(':');
  return colon == std::string_view::npos ? name : name.substr(colon + 1);
}

pugi::xml_node child(pugi::xml_node n, std::string_view name) {
  for (pugi::xml_node c = n.first_child(); c; c = c.next_sibling()) {
    if (c.type() == pugi::node_element && local_name(c) == name) return c;
  }
  return {};
}

// The <text> of a label such as <name> or <inscription>, if it has one.
std::optional<std::string_view> label_text(pugi::xml_node label) {
  pugi::xml_node text = child(label, "text");
  if (!text) return std::nullopt;
  return std::string_view(text.text().get());
}

// A count written in a <text>, whitespace around it allowed. Values over
// kMaxTokens come back as kMaxTokens + 1; anything else than digits as nullopt.
std::optional<std::uint64_t> parse_count(std::string_view s) {
  constexpr std::string_view kSpace = " \t\r\n";
  std::size_t first = s.find_first_not_of(kSpace);
  if (first == std::string_view::npos) return std::nullopt;
  s = s.substr(first, s.find_last_not_of(kSpace) - first + 1);
  std::uint64_t value = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return std::nullopt;
    value = std::min<std::uint64_t>(value * 10 + static_cast<unsigned>(c - '0'), kMaxTokens + 1ull);
  }
  return value;
}

// The elements with ids, named as in PNML.
enum class Kind { Place, Transition, RefPlace, RefTransition, Arc, Page, Net };
constexpr const char* kKindNames[] = {"place", "transition", "referencePlace", "referenceTransition", "arc",
                                      "page",  "net"};

const char* kind_name(Kind k) { return kKindNames[static_cast<int>(k)]; }

std::optional<Kind> kind_of(std::string_view element) {
  for (int k = 0; k < 7; ++k) {
    if (element == kKindNames[k]) return static_cast<Kind>(k);
  }
  return std::nullopt;
}

// One element with an id. For a place or transition, `target` is its
// PlaceId or TransitionId; for a reference node, that of the node it stands
// for once resolved.
struct Node {
  Kind kind;
  pugi::xml_node xml;
  std::uint32_t target = 0;
  enum class State : std::uint8_t { Unresolved, Visiting, Resolved } state = State::Resolved;
};

struct PendingArc {
  bool input;  // place -> transition
  TransitionId t;
  PlaceId p;
  std::uint64_t weight;
  pugi::xml_node xml;
};

class Reader {
 public:
  Reader(const std::string& text, const std::string& source) : text_(text), source_(source) {}
  core::Result<PnmlNet> read();

 private:
  // "line:col" of a byte offset in text_ (1-based, columns in bytes), or ""
  // when pugixml cannot tell the offset.
  std::string where(std::ptrdiff_t offset) const;
  std::string where(pugi::xml_node element) const {
    std::ptrdiff_t offset = element.offset_debug();  // of the name: step back to the '<'
    return where(offset > 0 ? offset - 1 : offset);
  }
  core::Error fail_at(const std::string& at, std::string_view message) const {
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("{}:{}{}{}", source_, at, at.empty() ? " " : ": ", message));
  }
  core::Error fail(pugi::xml_node at, std::string_view message) const { return fail_at(where(at), message); }
  core::Error unexpected(pugi::xml_node element, std::string_view in) const {
    return fail(element,
                fmt::format("<{}>{}{} is not part of a P/T net", element.name(), in.empty() ? "" : " in ", in));
  }
  core::Result<std::uint32_t> count(pugi::xml_node label, std::string_view what, std::string_view id,
                                    std::uint32_t min) const;
  core::Result<std::string_view> id_of(pugi::xml_node n, Kind kind);
  core::Result<void> walk(pugi::xml_node net);
  core::Result<void> read_node(pugi::xml_node n, Kind kind);
  core::Result<void> resolve(std::uint32_t node);
  core::Result<const Node*> arc_end(pugi::xml_node arc, const char* role);
  core::Result<void> read_arc(pugi::xml_node n, std::vector<PendingArc>& pending);
  core::Result<void> read_arcs();

  const std::string& text_;
  const std::string& source_;
  pugi::xml_document doc_;
  std::vector<Node> nodes_;
  std::unordered_map<std::string_view, std::uint32_t> by_id_;  // views into doc_
  std::vector<pugi::xml_node> arcs_;
  NetBuilder builder_;
  PnmlNet out_;
};

std::string Reader::where(std::ptrdiff_t offset) const {
  if (offset < 0) return "";
  // pugixml may put an error at end of text + 1.
  std::string_view before = std::string_view(text_).substr(0, std::min(text_.size(), std::size_t(offset)));
  auto line = 1 + std::count(before.begin(), before.end(), '\n');
  std::size_t line_start = before.rfind('\n');
  std::size_t col = line_start == std::string_view::npos ? before.size() + 1 : before.size() - line_start;
  return fmt::format("{}:{}", line, col);
}

// The number in a label's <text>, from min to kMaxTokens; `what` and `id`
// name the label in errors ("initial marking of place", "p1").
core::Result<std::uint32_t> Reader::count(pugi::xml_node label, std::string_view what, std::string_view id,
                                          std::uint32_t min) const {
  std::optional<std::string_view> text = label_text(label);
  std::optional<std::uint64_t> n = text ? parse_count(*text) : std::nullopt;
  if (!n || *n < min) {
    return fail(label, fmt::format("{} '{}' is '{}', not a {} integer", what, id, text.value_or(""),
                                   min == 0 ? "non-negative" : "positive"));
  }
  if (*n > kMaxTokens) {
    return fail(label, fmt::format("{} '{}' is over the limit of {}", what, id, kMaxTokens));
  }
  return static_cast<std::uint32_t>(*n);
}

// Registers the element's id (ids are unique across the whole document).
core::Result<std::string_view> Reader::id_of(pugi::xml_node n, Kind kind) {
  pugi::xml_attribute attr = n.attribute("id");
  if (!attr) return fail(n, fmt::format("<{}> has no id", kind_name(kind)));
  std::string_view id = attr.value();
  auto [it, fresh] = by_id_.try_emplace(id, static_cast<std::uint32_t>(nodes_.size()));
  if (!fresh) {
    return fail(n, fmt::format("duplicate id '{}' (first used at {})", id, where(nodes_[it->second].xml)));
  }
  nodes_.push_back({kind, n});
  return id;
}

bool is_decoration(std::string_view element) {
  return element == "name" || element == "graphics" || element == "toolspecific";
}

// The net and its pages, depth first in document order, so places and
// transitions are numbered as they appear in the file. Arcs wait until every
// node is known: they may name nodes further down.
core::Result<void> Reader::walk(pugi::xml_node net) {
  std::vector<pugi::xml_node> stack{net.first_child()};
  while (!stack.empty()) {
    pugi::xml_node n = stack.back();
    if (!n) {
      stack.pop_back();
      continue;
    }
    stack.back() = n.next_sibling();
    if (n.type() != pugi::node_element) continue;
    std::optional<Kind> kind = kind_of(local_name(n));
    core::Result<void> r;
    if (kind == Kind::Page || kind == Kind::Arc) {
      auto id = id_of(n, *kind);
      if (!id) return id.error();
      if (kind == Kind::Page)
        stack.push_back(n.first_child());
      else
        arcs_.push_back(n);
    } else if (kind && kind != Kind::Net) {
      r = read_node(n, *kind);
    } else if (!is_decoration(local_name(n))) {
      r = unexpected(n, "");
    }
    if (!r) return r;
  }
  return {};
}

// A place, a transition or a reference node: a name, graphics and tool
// data, and for a place its initial marking.
core::Result<void> Reader::read_node(pugi::xml_node n, Kind kind) {
  auto id = id_of(n, kind);
  if (!id) return id.error();
  std::optional<std::string_view> label;
  Tokens marking = 0;
  for (pugi::xml_node c : n.children()) {
    if (c.type() != pugi::node_element) continue;
    std::string_view name = local_name(c);
    if (name == "name") {
      label = label_text(c);
    } else if (name == "initialMarking" && kind == Kind::Place) {
      auto m = count(c, "initial marking of place", id.value(), 0);
      if (!m) return m.error();
      marking = m.value();
    } else if (!is_decoration(name)) {
      return unexpected(c, fmt::format("{} '{}'", kind_name(kind), id.value()));
    }
  }
  if (kind == Kind::Place) {
    nodes_.back().target = builder_.add_place(id.value(), marking);
    out_.place_labels.emplace_back(label.value_or(id.value()));
  } else if (kind == Kind::Transition) {
    nodes_.back().target = builder_.add_transition(id.value());
    out_.transition_labels.emplace_back(label.value_or(id.value()));
  } else {
    if (!n.attribute("ref")) return fail(n, fmt::format("{} '{}' has no ref", kind_name(kind), id.value()));
    nodes_.back().state = Node::State::Unresolved;
  }
  return {};
}

// Follows a reference node through its chain to the place or transition it
// stands for, and records the answer on every node of the chain.
core::Result<void> Reader::resolve(std::uint32_t start) {
  std::vector<std::uint32_t> chain;
  std::uint32_t cur = start;
  while (nodes_[cur].state == Node::State::Unresolved) {
    Node& node = nodes_[cur];
    node.state = Node::State::Visiting;
    chain.push_back(cur);
    auto what = [&] { return fmt::format("{} '{}'", kind_name(node.kind), node.xml.attribute("id").value()); };
    std::string_view ref = node.xml.attribute("ref").value();
    auto it = by_id_.find(ref);
    if (it == by_id_.end()) {
      return fail(node.xml, fmt::format("{} refers to '{}', which does not exist", what(), ref));
    }
    const Node& next = nodes_[it->second];
    Kind real = node.kind == Kind::RefPlace ? Kind::Place : Kind::Transition;
    if (next.kind != real && next.kind != node.kind) {
      return fail(node.xml,
                  fmt::format("{} refers to {} '{}', not to a {}", what(), kind_name(next.kind), ref, kind_name(real)));
    }
    if (next.state == Node::State::Visiting) {
      return fail(node.xml, fmt::format("{} is part of a reference cycle", what()));
    }
    cur = it->second;
  }
  for (std::uint32_t i : chain) {
    nodes_[i].target = nodes_[cur].target;
    nodes_[i].state = Node::State::Resolved;
  }
  return {};
}

core::Result<const Node*> Reader::arc_end(pugi::xml_node arc, const char* role) {
  std::string_view id = arc.attribute("id").value();
  pugi::xml_attribute attr = arc.attribute(role);
  if (!attr) return fail(arc, fmt::format("arc '{}' has no {}", id, role));
  auto it = by_id_.find(attr.value());
  if (it == by_id_.end()) {
    return fail(arc, fmt::format("arc '{}' has {} '{}', which does not exist", id, role, attr.value()));
  }
  const Node* end = &nodes_[it->second];
  if (end->kind == Kind::Arc || end->kind == Kind::Page || end->kind == Kind::Net) {
    return fail(arc, fmt::format("arc '{}' has {} '{}', which is a {}", id, role, attr.value(), kind_name(end->kind)));
  }
  return end;
}

core::Result<void> Reader::read_arc(pugi::xml_node n, std::vector<PendingArc>& pending) {
  std::string_view id = n.attribute("id").value();
  std::uint32_t weight = 1;
  for (pugi::xml_node c : n.children()) {
    if (c.type() != pugi::node_element) continue;
    std::string_view name = local_name(c);
    if (name == "inscription") {
      auto w = count(c, "inscription of arc", id, 1);
      if (!w) return w.error();
      weight = w.value();
    } else if (name == "type") {  // an extension for inhibitor, read and reset arcs
      std::string_view type = c.attribute("value").value();
      if (type != "normal") {
        return fail(c, fmt::format("{} arc '{}' is not supported: Strata reads P/T nets (ptnet)",
                                   type.empty() ? "typed" : type, id));
      }
    } else if (!is_decoration(name)) {
      return unexpected(c, fmt::format("arc '{}'", id));
    }
  }
  auto source = arc_end(n, "source");
  if (!source) return source.error();
  auto target = arc_end(n, "target");
  if (!target) return target.error();
  auto is_place = [](const Node* e) { return e->kind == Kind::Place || e->kind == Kind::RefPlace; };
  bool input = is_place(source.value());
  if (input == is_place(target.value())) {
    return fail(n, fmt::format("arc '{}' joins two {}s: an arc joins a place and a transition", id,
                               input ? "place" : "transition"));
  }
  const Node* t = input ? target.value() : source.value();
  const Node* p = input ? source.value() : target.value();
  pending.push_back({input, t->target, p->target, weight, n});
  return {};
}

core::Result<void> Reader::read_arcs() {
  std::vector<PendingArc> pending;
  pending.reserve(arcs_.size());
  for (pugi::xml_node n : arcs_) {
    if (auto r = read_arc(n, pending); !r) return r;
  }
  // Parallel arcs add up. The sum must still fit, so merge them here rather
  // than let NetBuilder saturate.
  std::stable_sort(pending.begin(), pending.end(), [](const PendingArc& a, const PendingArc& b) {
    if (a.input != b.input) return a.input < b.input;
    return a.t != b.t ? a.t < b.t : a.p < b.p;
  });
  auto parallel = [](const PendingArc& a, const PendingArc& b) {
    return a.input == b.input && a.t == b.t && a.p == b.p;
  };
  for (std::size_t i = 0; i < pending.size();) {
    PendingArc sum = pending[i];
    for (++i; i < pending.size() && parallel(pending[i], sum); ++i) {
      sum.weight += pending[i].weight;
      if (sum.weight > kMaxTokens) {
        return fail(pending[i].xml, fmt::format("arc '{}' and the arcs parallel to it weigh over {} in all",
                                                pending[i].xml.attribute("id").value(), kMaxTokens));
      }
    }
    auto w = static_cast<std::uint32_t>(sum.weight);
    if (sum.input)
      builder_.add_input(sum.t, sum.p, w);
    else
      builder_.add_output(sum.t, sum.p, w);
  }
  return {};
}

core::Result<PnmlNet> Reader::read() {
  pugi::xml_parse_result parsed =
      doc_.load_buffer(text_.data(), text_.size(), pugi::parse_default | pugi::parse_ws_pcdata_single);
  if (!parsed) return fail_at(where(parsed.offset), fmt::format("malformed XML: {}", parsed.description()));
  pugi::xml_node root = doc_.document_element();
  if (local_name(root) != "pnml") {
    return fail(root, fmt::format("not a PNML document: the root element is <{}>, not <pnml>", root.name()));
  }
  pugi::xml_node net;
  for (pugi::xml_node c : root.children()) {
    if (c.type() != pugi::node_element) continue;
    if (local_name(c) != "net") return fail(c, fmt::format("<{}> is not part of a PNML document", c.name()));
    if (net) return fail(c, "a second <net>: Strata reads one net per PNML file");
    net = c;
  }
  if (!net) return fail(root, "the PNML document holds no <net>");
  if (!net.attribute("type")) return fail(net, "<net> has no type: Strata reads P/T nets (ptnet)");
  if (std::string_view type = net.attribute("type").value(); type != kPtNetType) {
    return fail(net, fmt::format("net type '{}' is not supported: Strata reads P/T nets (ptnet)", type));
  }
  auto id = id_of(net, Kind::Net);
  if (!id) return id.error();
  out_.id = id.value();
  out_.name = label_text(child(net, "name")).value_or(id.value());

  if (auto r = walk(net); !r) return r.error();
  for (std::uint32_t i = 0; i < nodes_.size(); ++i) {
    if (auto r = resolve(i); !r) return r.error();
  }
  if (auto r = read_arcs(); !r) return r.error();
  out_.net = std::move(builder_).build();
  return std::move(out_);
}

}  // namespace

core::Result<PnmlNet> parse_pnml(const std::string& text, const std::string& source_name) {
  return Reader(text, source_name).read();
}

core::Result<PnmlNet> read_pnml(const std::string& path) {
  auto text = core::read_regular_file(path, kMaxPnmlBytes, [](const std::string& p, const char* reason) {
    return fmt::format("cannot open '{}': {}", p, reason);
  });
  if (!text) return text.error();
  return parse_pnml(std::move(text).value(), path);
}

}  // namespace strata::petri
