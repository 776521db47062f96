#pragma once
// Expected runtime failures (a file that cannot be read, a peer that closed)
// travel as Result<T>; broken invariants are asserted instead. A layer whose
// failures carry more than a core::Error names its own error type E (the
// protocol's DecodeError, which keeps the request id and the wire's error
// code); such an E has `core::Error to_core() const`, and to_core() turns the
// result into a plain Result<T> at the boundary.
#include <cassert>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>

namespace strata::core {

enum class ErrorCode { Io, InvalidInput, Overflow, Timeout, Closed, Protocol, Internal };

struct Error {
  ErrorCode code = ErrorCode::Internal;
  std::string message;
};

template <typename T, typename E = Error>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::move(value)) {}  // NOLINT: implicit by design
  Result(E error) : v_(std::move(error)) {}  // NOLINT

  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }

  T& value() & {
    assert(ok());
    return std::get<0>(v_);
  }
  const T& value() const& {
    assert(ok());
    return std::get<0>(v_);
  }
  T&& value() && {
    assert(ok());
    return std::get<0>(std::move(v_));
  }
  const E& error() const {
    assert(!ok());
    return std::get<1>(v_);
  }

  // The same result with its error as a core::Error (E::to_core()).
  Result<T> to_core() && requires(!std::is_same_v<E, Error>) {
    if (ok()) return std::get<0>(std::move(v_));
    return error().to_core();
  }

 private:
  std::variant<T, E> v_;
};

template <typename E>
class [[nodiscard]] Result<void, E> {
 public:
  Result() = default;
  Result(E error) : error_(std::move(error)), ok_(false) {}  // NOLINT

  bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  const E& error() const {
    assert(!ok_);
    return error_;
  }

 private:
  E error_;
  bool ok_ = true;
};

inline Error make_error(ErrorCode code, std::string message) { return {code, std::move(message)}; }

}  // namespace strata::core
