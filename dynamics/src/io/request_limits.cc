#include "tether/dynamics/io/request_limits.h"

#include "tether/dynamics/model/errors.h"

namespace tether {

int CheckCount(int value, int low, int high, const std::string& what) {
  if (value < low || value > high) {
    throw InputError(what + ": must be a whole number from " + std::to_string(low) + " to " + std::to_string(high) +
                     ", got " + std::to_string(value));
  }
  return value;
}

}  // namespace tether
