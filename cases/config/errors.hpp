#pragma once
// The error channels of a case run (docs/design.md, "Contracts"): bad input (exit 2)
// located at file:line:column, numerical failure (exit 3) and output not written (exit 4). A failed check is not an
// exception: `radnet check` counts failures and exits 1.
#include <stdexcept>
#include <string>

namespace radnet::cases {

/// Bad input. what() reads "FILE:LINE:COLUMN: MESSAGE" (1-based line and column;
/// 0 when the problem has no position, e.g. a file that cannot be opened).
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, int line, int column, const std::string& message)
      : std::runtime_error(file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + message),
        file_(file),
        line_(line),
        column_(column) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }

 private:
  std::string file_;
  int line_;
  int column_;
};

/// The output could not be written (exit 4): a file that cannot be created, a full disk, a
/// rename that fails. Nothing partial is left under the requested name.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A numerical failure: no convergence, singular system, non-finite result.
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace radnet::cases
