#pragma once
// The script message of a primitive, as written in the catalogue:
// "exec sleep {seconds}". Fields are separated by single or repeated spaces;
// the first is the verb, the second the function's name on the wire, the rest
// argument fields. A field is literal text with {placeholders}, each naming an
// argument (or, for data primitives, a setpoint field). Braces have no escape:
// the wire protocol has no use for them.
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace strata::tactical {

struct TemplatePiece {
  bool is_placeholder = false;
  std::string text;  // the literal text, or the placeholder's name
};

struct TemplateField {
  std::vector<TemplatePiece> pieces;
  bool is_literal() const { return pieces.size() == 1 && !pieces[0].is_placeholder; }
};

struct MessageTemplate {
  std::vector<TemplateField> fields;
};

// Splits and checks the syntax (balanced braces, placeholder names are
// identifiers). Errors are InvalidInput, without location: the caller knows
// where the message came from.
core::Result<MessageTemplate> parse_message_template(std::string_view message);

// [A-Za-z_][A-Za-z0-9_]*
bool is_identifier(std::string_view text);

}  // namespace strata::tactical
