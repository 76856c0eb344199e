#include "tether/dynamics/model/errors.h"

#include <cstdio>

namespace tether {

std::string Printable(const std::string& text) {
  std::string printable;
  printable.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte != 0x7f) {
      printable += c;
      continue;
    }
    char escaped[7];
    std::snprintf(escaped, sizeof escaped, "\\u%04x", byte);
    printable += escaped;
  }
  return printable;
}

std::string ListWithOr(const std::vector<std::string>& names) {
  std::string list;
  const size_t n = names.size();
  for (size_t k = 0; k < n; ++k) list += std::string(k == 0 ? "" : k + 1 == n ? " or " : ", ") + names[k];
  return list;
}

}  // namespace tether
