// The ways a run can fail, kept apart (docs/architecture.md, principle 12): bad input (the user can fix the scene or
// the flags; exit status 2), a simulation that diverges and an output that cannot be written (exit status 1). Internal
// invariants use assert.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace tether {

// `text` with every control character (NUL, ESC, line breaks) written as \u00XX, as JSON writes it. Messages
// quote the user's keys and names; printed raw, a NUL would cut them short and an escape sequence would drive
// the terminal. Both exceptions below pass their message through it.
std::string Printable(const std::string& text);

// "a, b or c": the names a message offers as the choices, in order.
std::string ListWithOr(const std::vector<std::string>& names);

// The input cannot be used as given; what() names the place (JSON Pointer, flag) and what is wrong.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(Printable(message)) {}
};

// The state became non-finite or a constraint ran away; what() says when and which constraint.
class SimulationDiverged : public std::runtime_error {
 public:
  SimulationDiverged(const std::string& message, double time, int constraint)
      : std::runtime_error(Printable(message)), time_(time), constraint_(constraint) {}
  double time() const { return time_; }
  int constraint() const { return constraint_; }  // scene index, or -1 when no constraint is at fault

 private:
  double time_;
  int constraint_;
};

// A run stopped by an interruption (Ctrl-C) while a CancelRuns was held (interrupts.h).
class RunInterrupted : public std::runtime_error {
 public:
  explicit RunInterrupted(int signal)
      : std::runtime_error("interrupted by signal " + std::to_string(signal)), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

// Writing an output failed on the way (a full disk, a closed device): exit status 1, as a failed run.
class OutputError : public std::runtime_error {
 public:
  explicit OutputError(const std::string& message) : std::runtime_error(Printable(message)) {}
};

}  // namespace tether
