#pragma once
// A small expected type for algorithm results (std::expected is C++23): either a value or an
// error message that names the cause. Used inside dsw where a failure is an expected outcome of
// bad geometry (degenerate polygon, point the coordinates cannot encode), not a bug.

#include <stdexcept>
#include <string>
#include <utility>
#include <variant>

namespace garmcap::dsw {

/// The error half of Expected: a message naming what failed and why.
struct Error {
  std::string message;
};

template <typename T>
class Expected {
 public:
  Expected(T value) : data_(std::move(value)) {}      // NOLINT: implicit by design
  Expected(Error error) : data_(std::move(error)) {}  // NOLINT: implicit by design

  bool ok() const { return std::holds_alternative<T>(data_); }
  explicit operator bool() const { return ok(); }

  /// The value; throws std::logic_error with the error message when there is none (a caller
  /// that did not check is a bug, and the message still says why the value is missing).
  const T& value() const& {
    if (!ok())
      throw std::logic_error("dsw: no value: " + error().message);
    return std::get<T>(data_);
  }
  T& value() & {
    if (!ok())
      throw std::logic_error("dsw: no value: " + error().message);
    return std::get<T>(data_);
  }
  T&& value() && {
    if (!ok())
      throw std::logic_error("dsw: no value: " + error().message);
    return std::get<T>(std::move(data_));
  }
  const T& operator*() const& { return value(); }
  const T* operator->() const { return &value(); }

  const Error& error() const { return std::get<Error>(data_); }

 private:
  std::variant<T, Error> data_;
};

}  // namespace garmcap::dsw
