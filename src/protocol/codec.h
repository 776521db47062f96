#pragma once
// One encoder and one decoder for both ends of the link: the vehicle decodes
// requests and encodes its messages, the tactical client the other way round.
// Pure functions; no I/O. docs/protocol.md is the table they implement.
#include <cassert>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

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

// A decoded message or the reason it could not be; the same shape as
// core::Result, with a DecodeError instead of a core::Error.
template <typename T>
class [[nodiscard]] DecodeResult {
 public:
  DecodeResult(T value) : v_(std::move(value)) {}  // NOLINT: implicit by design
  DecodeResult(DecodeError error) : v_(std::move(error)) {}  // NOLINT

  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }

  T& value() & { assert(ok()); return std::get<0>(v_); }
  const T& value() const& { assert(ok()); return std::get<0>(v_); }
  T&& value() && { assert(ok()); return std::get<0>(std::move(v_)); }
  const DecodeError& error() const { assert(!ok()); return std::get<1>(v_); }

  core::Result<T> to_core() && {
    if (ok()) return std::get<0>(std::move(v_));
    return error().to_core();
  }

 private:
  std::variant<T, DecodeError> v_;
};

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
