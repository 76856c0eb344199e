// Comparing CSV files whose columns include wall times (study results): drop a column by its header name.
#pragma once

#include <string>

namespace tether::testing {

// The CSV text with the column named `drop` removed from every line (cells joined by ';', lines by '\n').
std::string WithoutColumn(const std::string& csv, const std::string& drop);

}  // namespace tether::testing
