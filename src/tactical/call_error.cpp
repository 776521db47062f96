#include "tactical/call_error.h"

namespace strata::tactical {

core::Error CallError::to_core() const {
  switch (kind) {
    case Kind::TimedOut: return core::make_error(core::ErrorCode::Timeout, message);
    case Kind::LinkLost: return core::make_error(core::ErrorCode::Closed, message);
    case Kind::Refused:
    case Kind::BadReply: return core::make_error(core::ErrorCode::Protocol, message);
    case Kind::BadCall:
    case Kind::Withheld: return core::make_error(core::ErrorCode::InvalidInput, message);
  }
  return core::make_error(core::ErrorCode::Internal, message);
}

std::string_view kind_name(CallError::Kind kind) {
  switch (kind) {
    case CallError::Kind::Refused: return "refused";
    case CallError::Kind::TimedOut: return "timed_out";
    case CallError::Kind::LinkLost: return "link_lost";
    case CallError::Kind::BadReply: return "bad_reply";
    case CallError::Kind::BadCall: return "bad_call";
    case CallError::Kind::Withheld: return "withheld";
  }
  return "?";
}

CallError call_error_from_link(const core::Error& error) {
  CallError e;
  e.message = error.message;
  switch (error.code) {
    case core::ErrorCode::Timeout: e.kind = CallError::Kind::TimedOut; break;
    case core::ErrorCode::Closed:
    case core::ErrorCode::Io: e.kind = CallError::Kind::LinkLost; break;
    case core::ErrorCode::InvalidInput: e.kind = CallError::Kind::Refused; break;
    case core::ErrorCode::Protocol:
    case core::ErrorCode::Overflow:
    case core::ErrorCode::Internal: e.kind = CallError::Kind::BadReply; break;
  }
  return e;
}

}  // namespace strata::tactical
