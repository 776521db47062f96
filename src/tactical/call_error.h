#pragma once
// Why a primitive call got no answer (1 or 0), as a value its callers switch
// on. The message is for people and the mission log; no caller reads it to
// decide anything, so rewording one changes no verdict.
//
// What each link error becomes (execution_link.h): Timeout -> TimedOut;
// Closed and Io -> LinkLost; InvalidInput (the link cannot carry the call:
// an IMC vehicle has no such function, or a number argument it needs is
// not one) -> Refused; Protocol (an answer that cannot be used) -> BadReply.
// A Phoenix vehicle's `err` reply is Refused with its code.
#include <optional>
#include <string>
#include <string_view>

#include "core/result.h"
#include "protocol/message.h"

namespace strata::tactical {

struct CallError {
  enum class Kind {
    Refused,   // the Execution level would not run it; vehicle_code says why when it sent an `err`
    TimedOut,  // no reply within the call's timeout (the vehicle's time in lockstep)
    LinkLost,  // no link, or the link closed or was lost before the reply
    BadReply,  // the vehicle's answer could not be used: malformed, of the wrong kind, or `err 0 busy`
    BadCall,   // never sent: an unknown primitive, arguments the catalogue refuses, no mission data or past its end
    Withheld,  // never sent: the run held it back (it left its scripted answers)
  };
  Kind kind = Kind::BadCall;
  std::optional<protocol::ErrorCode> vehicle_code;  // Refused by an `err` reply: its CODE
  std::string message;                              // for people and the log

  // For boundaries that speak core::Error: TimedOut -> Timeout, LinkLost ->
  // Closed, Refused and BadReply -> Protocol, BadCall and Withheld ->
  // InvalidInput; the message is kept.
  core::Error to_core() const;
  // The link to the vehicle is gone or silent: TimedOut or LinkLost.
  bool link_gone() const { return kind == Kind::TimedOut || kind == Kind::LinkLost; }
};

// "refused", "timed_out", "link_lost", "bad_reply", "bad_call", "withheld".
std::string_view kind_name(CallError::Kind kind);

// A link's error (execution_link.h) as a call error, kind by its code.
CallError call_error_from_link(const core::Error& error);

}  // namespace strata::tactical
