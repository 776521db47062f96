#include "run/error.h"

namespace strata::run {

std::string_view to_string(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::Usage: return "usage";
    case ErrorKind::Unreadable: return "unreadable";
    case ErrorKind::Invalid: return "invalid";
    case ErrorKind::FailsVerification: return "fails_verification";
    case ErrorKind::LogUnwritable: return "log_unwritable";
    case ErrorKind::VehicleUnavailable: return "vehicle_unavailable";
  }
  return "invalid";
}

Error input_error(const core::Error& error, std::string input) {
  return Error{error.code == core::ErrorCode::Io ? ErrorKind::Unreadable : ErrorKind::Invalid, std::move(input),
               error.message, std::nullopt};
}

}  // namespace strata::run
