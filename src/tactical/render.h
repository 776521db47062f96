#pragma once
// From a primitive call (a catalogue entry and literal arguments) to the
// script message the Tactical level sends. The result carries the message's
// parts separately so the protocol layer can build its Request{verb, id,
// name, args}; the request id is the protocol's business and never appears
// here.
//
// Numbers are normalised: sleep(1), sleep(1.0) and PROLOG's exec_sleep(1,X)
// all render as the number 1 ("exec sleep 1"), so the two executors issue
// identical calls (strata compare).
#include <span>
#include <string>
#include <vector>

#include "core/call_verb.h"
#include "core/result.h"
#include "tactical/catalogue.h"
#include "tactical/mission_data.h"
#include "tactical/value.h"

namespace strata::tactical {

struct RenderedCall {
  core::CallVerb verb = core::CallVerb::Exec;  // the primitive's kind; report: nothing is sent
  std::string name;                            // the function's name on the wire ("setpoint" for next_setpt_data)
  // The argument fields, filled. A field that is exactly one placeholder
  // keeps its argument's type (number or string); a field with literal text
  // around or instead of placeholders is a string. For report: { text }.
  std::vector<Value> args;
  double timeout_s = 0;  // the reply timeout for this call (timeout_s + timeout_plus_arg)

  bool to_vehicle() const { return verb != core::CallVerb::Report; }
  // "exec sleep 1": verb, name and args (to_string) joined by single spaces;
  // for report, the text. For the log and for people; the wire line is built
  // by the protocol layer, which adds the request id.
  std::string text() const;
};

// Checks the arguments against the primitive (count, type, range, finite
// numbers) and returns them with defaults filled in.
core::Result<std::vector<Value>> check_args(const Primitive& primitive, std::span<const Value> args);

// Checks the arguments and fills the message template. A data primitive
// (data = "setpoint") reads cursor->current(): the caller has advanced the
// cursor already (see advance_and_render). String values that go into a
// message field must be one token: non-empty, no spaces or control
// characters. Errors are InvalidInput and name the primitive.
core::Result<RenderedCall> render(const Primitive& primitive, std::span<const Value> args, const DataCursor* cursor);

// What the Tactical level does for a call: checks the arguments, advances the
// cursor if the primitive reads a setpoint (so a bad call consumes nothing),
// then renders.
core::Result<RenderedCall> advance_and_render(const Primitive& primitive, std::span<const Value> args,
                                              DataCursor& cursor);

}  // namespace strata::tactical
