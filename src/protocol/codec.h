#pragma once
// One encoder and one decoder for both ends of the link: the vehicle decodes
// requests and encodes its messages, the tactical client the other way round.
// Pure functions; no I/O. docs/protocol.md is the table they implement.
#include <string>
#include <string_view>

#include "core/result.h"
#include "protocol/message.h"

namespace strata::protocol {

// Why a line could not be decoded, with what the receiver needs to answer it:
// the vehicle replies `err id code "message"` (encode(to_err(e))); the client,
// which never sends err, logs it and fails request `id` if it is in flight.
struct DecodeError {
  ErrorCode code = ErrorCode::BadLine;
  RequestId id = 0;  // 0 when the line had no readable id
  std::string message;

  // For the Result<T> channel: core::ErrorCode::Protocol, "code: message".
  core::Error to_core() const;
};

Err to_err(const DecodeError& e);

// A decoded message or the reason it could not be: core::Result with a
// DecodeError for its error (to_core() gives the plain core::Result<T>).
template <typename T>
using DecodeResult = core::Result<T, DecodeError>;

// One line ending in "\n". Strings that the grammar cannot carry lose their
// unprintable bytes ('?'); the free text of err and event is cut (ending in
// "...") so the line stays within kMaxLineBytes. Other fields are not cut:
// keep names and arguments short (the catalogue does) or the receiver
// answers too_long. Values must be finite; telemetry extras whose key is a
// known key, or is not a bare token, are left out.
std::string encode(const Request& request);
std::string encode(const VehicleMessage& message);

// `line` is one line, with or without its "\n" / "\r\n". Never throws; any
// input gives a value or a DecodeError.
DecodeResult<Request> decode_request(std::string_view line);
DecodeResult<VehicleMessage> decode_vehicle_message(std::string_view line);

// The id in a line's second field, 0 when there is none: for answering a
// line that is not otherwise readable, e.g. the kept start of a too_long one.
RequestId peek_id(std::string_view line);

}  // namespace strata::protocol
