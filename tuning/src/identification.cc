#include "tether/tuning/identification.h"

#include <cmath>
#include <cstdlib>
#include <limits>

#include "tether/dynamics/model/errors.h"

namespace tether {

InequalityTarget ParseInequality(const std::string& text, bool at_least, const std::string& flag) {
  const size_t at = text.rfind('@'), equals = text.rfind('=', at);
  if (at == std::string::npos || equals == std::string::npos || equals == 0) {
    throw InputError(flag + ": '" + text + "' is not COLUMN=VALUE@T or COLUMN=VALUE@T0:T1 (e.g. tip.y=1.99@5)");
  }
  const auto number = [&](const std::string& s) {
    char* end = nullptr;
    const double x = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(x)) {
      throw InputError(flag + ": '" + text + "': '" + s + "' is not a finite number");
    }
    return x;
  };
  const std::string when = text.substr(at + 1);
  const size_t colon = when.find(':');
  InequalityTarget target{text.substr(0, equals), number(text.substr(equals + 1, at - equals - 1)),
                          number(when.substr(colon == std::string::npos ? 0 : colon + 1)), at_least, flag + " " + text};
  target.from = colon == std::string::npos ? target.time : number(when.substr(0, colon));
  if (!(target.from <= target.time)) {
    throw InputError(flag + ": '" + text + "': the interval must run forward (T0 < T1)");
  }
  return target;
}

std::vector<std::pair<double, double>> BoundsFor(const ParameterSet& parameters,
                                                 const std::vector<ParameterBound>& bounds, const std::string& where) {
  constexpr double kLargest = std::numeric_limits<double>::max();
  std::vector<std::pair<double, double>> out(parameters.size(), {-kLargest, kLargest});
  const std::vector<std::string>& pointers = parameters.pointers();
  for (const bool wildcards : {true, false}) {
    for (const ParameterBound& b : bounds) {
      const bool wildcard = EndsInWildcard(b.pointer);
      if (wildcard != wildcards) continue;
      const std::string prefix = wildcard ? b.pointer.substr(0, b.pointer.size() - 1) : b.pointer;  // ".../"
      bool matched = false;
      for (size_t i = 0; i < pointers.size(); ++i) {
        const bool match = wildcard ? pointers[i].compare(0, prefix.size(), prefix) == 0 &&
                                          pointers[i].find('/', prefix.size()) == std::string::npos
                                    : pointers[i] == b.pointer;
        if (!match) continue;
        out[i] = {b.lower, b.upper};
        matched = true;
      }
      if (!matched) throw InputError(where + ": '" + b.pointer + "' is not one of the parameters");
    }
  }
  return out;
}

}  // namespace tether
