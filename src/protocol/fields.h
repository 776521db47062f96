#pragma once
// The field grammar every line shares (docs/protocol.md, "Fields"):
//   field  = bare | quoted
//   bare   = 1*( ALPHA / DIGIT / "_" / "." / ":" / "+" / "-" / "/" / "=" )
//   quoted = '"' *( printable-but-'"'-or-'\' / '\"' / '\\' / '\n' / '\t' ) '"'
//   number = ["-"] 1*DIGIT ["." 1*DIGIT] [("e"/"E") ["+"/"-"] 1*DIGIT]   (finite)
// Fields are separated by one or more spaces; a line is printable ASCII only.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "protocol/message.h"

namespace strata::protocol {

struct Field {
  std::string text;  // escapes already applied when quoted
  bool quoted = false;
  std::size_t column = 0;  // 1-based, where the field starts
};

struct SplitResult {
  std::vector<Field> fields;  // the fields read before the first error
  std::string error;          // empty when the whole line was read
  bool ok() const { return error.empty(); }
};

// Splits one line (without its terminator) into at most kMaxFields fields.
SplitResult split_fields(std::string_view line);

bool is_bare_char(char c);
// Non-empty and made of bare characters only.
bool is_bare_token(std::string_view text);

// `"..."` with \" \\ \n \t escaped. Bytes the grammar cannot carry (other
// control bytes, non-ASCII) become '?', so the result always parses.
std::string quote(std::string_view text);
// Like quote(), but at most max_bytes long (max_bytes >= 5): a text that does
// not fit is cut and ends in "...".
std::string quote_within(std::string_view text, std::size_t max_bytes);
// The text as a bare token when it is one, quoted otherwise.
std::string bare_or_quoted(std::string_view text);

// The shortest decimal form that reads back to exactly d, always with a '.'
// or an exponent so that it reads back as a float ("1.0", "0.6", "1e+20").
// d must be finite.
std::string format_double(double d);
// A number token as a Value: Integer when it has no '.' and no exponent,
// Float otherwise. Fails (InvalidInput) on anything else, out-of-range
// integers, and floats that overflow.
core::Result<Value> parse_number(std::string_view token);
// Any number token as a double (integers are accepted too).
std::optional<double> parse_double(std::string_view token);
// A request id: decimal digits, 1..kMaxRequestId (0 too when allow_zero).
std::optional<RequestId> parse_id(std::string_view token, bool allow_zero = false);

}  // namespace strata::protocol
