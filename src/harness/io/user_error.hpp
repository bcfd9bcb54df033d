#pragma once
/// @file user_error.hpp
/// The one type of error a user can cause: a bad scenario or option, a missing or malformed
/// input file, an output folder that cannot be written. The command line prints its message
/// on one line and exits 2; every other exception is a bug in clothbench (exit 70).

#include <stdexcept>
#include <string>

namespace clothbench {

/// An error the user caused and can fix; what() names where, what is wrong and what is
/// expected, e.g. "out/x/stability.csv:4: stable_dt: expected a number, got \"abc\"".
class UserError : public std::runtime_error {
 public:
  explicit UserError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace clothbench
