#pragma once

#include <stdexcept>
#include <string>

namespace mimpact {

// Base of every exception mimpact throws, so an application can catch the library's errors
// in one place. The message names the offending field, its value and what is allowed.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Input that violates a documented precondition (a negative stiffness, sizes that disagree).
class InvalidInput : public Error {
 public:
  using Error::Error;
};

// A run that spent the work its caller allowed (a budget of steps) by `time` (s), before its end.
class BudgetSpent : public Error {
 public:
  BudgetSpent(const std::string& message, double time) : Error(message), time_(time) {}
  double time() const { return time_; }

 private:
  double time_;
};

// A run stopped at the wall-clock time its caller allowed (--max-seconds, max_seconds=): not
// a result, and not caught by a phase that would report a budget spent as a figure not made.
class TimeLimitReached : public Error {
 public:
  using Error::Error;
};

// The shortest text that reads back as the same double: 1e-09, not 0.000000 or
// 1.0000000000000001e-09.
std::string to_text(double value);

// The value to three significant digits, for estimates: "3.26e+13", "0.5".
std::string rounded_text(double value);

// Formats "FIELD = VALUE is invalid; allowed: ALLOWED", the one shape of every input error.
std::string invalid_value_message(const std::string& field, double value,
                                  const std::string& allowed);

}  // namespace mimpact
