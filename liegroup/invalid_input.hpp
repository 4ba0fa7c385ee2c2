/// \file
/// The exception thrown by every checked factory of lieflow: the message names
/// the field and the reason, e.g. "bodies[2].orientation: quaternion norm 0.5 is
/// not within 1e-06 of 1".
#pragma once

#include <stdexcept>
#include <string>

namespace lieflow {

/// Bad input that a caller can report and fix (exit status 2 in the `lieflow`
/// command). `field()` is the name of the offending input, `reason()` the why.
/// An option of the library's option structs is named, in the field and in
/// the reason, as its member in backquotes ("`max_steps`", "`use` gyroscopes"):
/// the library does not know how a caller spelled it. The command line and
/// the Python module print it as their flag (--max-steps; app/flag_spelling.hpp).
class InvalidInput : public std::invalid_argument {
 public:
  InvalidInput(const std::string& field, const std::string& reason)
      : std::invalid_argument(field.empty() ? reason : field + ": " + reason),
        field_(field),
        reason_(reason) {}
  const std::string& field() const { return field_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string field_;
  std::string reason_;
};

}  // namespace lieflow
