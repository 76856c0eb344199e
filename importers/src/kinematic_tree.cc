#include "tether/importers/kinematic_tree.h"

namespace tether::importers {

std::string ListWarning(const std::string& what, const std::vector<std::string>& names, size_t shown) {
  std::string out = what + ": ";
  for (size_t k = 0; k < names.size() && k < shown; ++k) out += (k > 0 ? ", " : "") + names[k];
  if (names.size() > shown) out += " (and " + std::to_string(names.size() - shown) + " more)";
  return out;
}

}  // namespace tether::importers
